"""Deprecated: the YAML and JSON loaders moved to :mod:`springbalance.loaders` (below every layer that reads a
file). The names stay importable from here for one release, with a DeprecationWarning."""

from __future__ import annotations

from springbalance import loaders
from springbalance.deprecation import moved_names

_MOVED = (
    "MAX_BYTES",
    "MAX_DEPTH",
    "MAX_VALUES",
    "DuplicateKeyError",
    "LimitError",
    "ConfigLoader",
    "load_json",
    "load_yaml",
)

__getattr__ = moved_names(__name__, {name: (loaders, name) for name in _MOVED})
