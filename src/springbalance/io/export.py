"""Deprecated: the exports' shared pieces moved to :mod:`springbalance.export.common`.

Importing a name from here still works for one release, with a :class:`DeprecationWarning`.
"""

from __future__ import annotations

from springbalance.deprecation import moved_names
from springbalance.export import common

_MOVED = {
    "ExportReport": "ExportReport",
    "GROUND": "GROUND",
    "anchor_link_name": "anchor_link_name",
    "law_warnings": "law_warnings",
}


__getattr__ = moved_names(__name__, {name: (common, new) for name, new in _MOVED.items()})
