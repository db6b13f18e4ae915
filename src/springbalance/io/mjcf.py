"""Deprecated: the MuJoCo export moved to :mod:`springbalance.export.mjcf`.

Importing a name from here still works for one release, with a :class:`DeprecationWarning`.
"""

from __future__ import annotations

import warnings
from typing import Any

from springbalance.export import mjcf

_MOVED = ("MUJOCO_MESH_FORMATS", "export_mjcf", "mjcf_string")


def __getattr__(name: str) -> Any:
    """The names that moved to :mod:`springbalance.export.mjcf` (deprecated, for one release)."""
    if name not in _MOVED:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(f"{__name__}.{name} is deprecated; use springbalance.export.mjcf.{name}", DeprecationWarning,
                  stacklevel=2)
    return getattr(mjcf, name)
