"""Deprecated: the YAML and JSON loaders moved to :mod:`springbalance.loaders` (below every layer that reads a
file). The names stay importable from here for one release, with a DeprecationWarning."""

from __future__ import annotations

import warnings
from typing import Any

from springbalance import loaders

_MOVED = ("MAX_BYTES", "MAX_DEPTH", "MAX_NODES", "DuplicateKeyError", "LimitError", "load_json", "load_yaml")


def __getattr__(name: str) -> Any:
    if name in _MOVED or hasattr(loaders, name):
        warnings.warn(f"springbalance.io.yaml_loader.{name} moved to springbalance.loaders.{name}; the old path "
                      "will be removed in springbalance 0.3", DeprecationWarning, stacklevel=2)
        return getattr(loaders, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
