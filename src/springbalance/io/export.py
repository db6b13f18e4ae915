"""Deprecated: the exports' shared pieces moved to :mod:`springbalance.export.common`.

Importing a name from here still works for one release, with a :class:`DeprecationWarning`.
"""

from __future__ import annotations

import warnings
from typing import Any

from springbalance.export import common

_MOVED = {"ExportReport": "ExportReport", "GROUND": "GROUND", "anchor_link_name": "anchor_link_name",
          "law_warnings": "law_warnings"}


def __getattr__(name: str) -> Any:
    """The names that moved to :mod:`springbalance.export.common` (deprecated, for one release)."""
    if name not in _MOVED:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(f"{__name__}.{name} is deprecated; use springbalance.export.common.{_MOVED[name]}",
                  DeprecationWarning, stacklevel=2)
    return getattr(common, _MOVED[name])
