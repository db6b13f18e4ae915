"""Deprecated: the MuJoCo export moved to :mod:`springbalance.export.mjcf`.

Importing a name from here still works for one release, with a :class:`DeprecationWarning`.
"""

from __future__ import annotations

from springbalance.deprecation import moved_names
from springbalance.export import mjcf

_MOVED = ("MUJOCO_MESH_FORMATS", "export_mjcf", "mjcf_string")


__getattr__ = moved_names(__name__, {name: (mjcf, name) for name in _MOVED})
