"""How the config code reports a problem: one line, starting with the file and the key path of the culprit.

:func:`prefixed` turns an :class:`~springbalance.errors.InputError` of the library (a URDF that
does not load, a workspace that cannot be sampled, ...) into a :class:`~springbalance.errors.ConfigError`
that starts with the key path (``config.yaml: mechanism.urdf: ...``); :func:`check_finite` rejects
``.nan`` and ``.inf`` anywhere in a parsed file.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from typing import Any

from springbalance.errors import ConfigError, InputError


def check_finite(record: Any, label: str, path: str = "") -> None:
    """Reject ``.nan`` / ``.inf`` anywhere in a parsed file, naming its key path (a rule of the whole file,
    checked before the schema)."""
    if isinstance(record, dict):
        for key, value in record.items():
            check_finite(value, label, f"{path}.{key}" if path else str(key))
    elif isinstance(record, list):
        for index, value in enumerate(record):
            check_finite(value, label, f"{path}[{index}]")
    elif isinstance(record, float) and not math.isfinite(record):
        raise ConfigError(f"{label}: {path or 'value'}: {record!r} is not allowed; every number must be finite")


def one_line(error: BaseException) -> str:
    """The message of ``error`` on one line (its type name when it has none)."""
    return " ".join(str(error).split()) or type(error).__name__


@contextlib.contextmanager
def prefixed(where: str, config_errors: bool = False) -> Iterator[None]:
    """Re-raise an :class:`InputError` of the library as a one-line :class:`ConfigError` that starts
    with ``where`` (the config key path). ConfigErrors raised inside pass unchanged, unless
    ``config_errors`` (the file-level guard): then they too get ``where`` in front when they lack it."""
    try:
        yield
    except ConfigError as error:
        if not config_errors or str(error).startswith(where):
            raise
        raise ConfigError(f"{where}: {one_line(error)}") from None
    except InputError as error:
        message = one_line(error)
        if config_errors and message.startswith(where):
            raise ConfigError(message) from None
        raise ConfigError(f"{where}: {message}") from None


def errors_as_config_errors(label: str) -> contextlib.AbstractContextManager[None]:
    """Every :class:`InputError` leaves as a one-line :class:`ConfigError` that starts with ``label``."""
    return prefixed(label, config_errors=True)
