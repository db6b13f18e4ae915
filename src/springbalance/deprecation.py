"""Deprecated names: one warning, one message, for one release (they go in springbalance 0.3).

:func:`warn_deprecated` is called by a deprecated function or method; :func:`moved_names` makes the module
``__getattr__`` that serves the names a module lost to another, each with a :class:`DeprecationWarning`
naming the new home.
"""

from __future__ import annotations

import warnings
from types import ModuleType
from typing import Any, Callable, Mapping

#: the release that removes the deprecated names
REMOVED_IN = "0.3"


def warn_deprecated(old: str, new: str, stacklevel: int = 3) -> None:
    """Warn that ``old`` is deprecated in favour of ``new`` (``stacklevel`` 3: the caller of the deprecated function)."""
    warnings.warn(
        f"{old} is deprecated; use {new} ({old} goes in springbalance {REMOVED_IN})",
        DeprecationWarning,
        stacklevel=stacklevel,
    )


def moved_names(module: str, names: Mapping[str, tuple[ModuleType, str]]) -> Callable[[str], Any]:
    """A module ``__getattr__`` for ``module``: each old name of ``names`` → ``(new module, new name)`` is
    served from its new home with a DeprecationWarning; any other name is an AttributeError."""

    def __getattr__(name: str) -> Any:
        if name not in names:
            raise AttributeError(f"module {module!r} has no attribute {name!r}")
        home, new = names[name]
        warn_deprecated(f"{module}.{name}", f"{home.__name__}.{new}")
        return getattr(home, new)

    return __getattr__
