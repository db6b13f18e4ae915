"""Reading an input file (config, catalogue) with a one-line error that names it."""

from __future__ import annotations

from pathlib import Path

from springbalance.errors import InputError


def read_input_text(path: str | Path, what: str, error: type[InputError] = InputError,
                    encoding: str = "utf-8") -> str:
    """The text of ``path``; raises ``error`` naming ``what`` (e.g. "config file") and the path when the
    file is missing, a directory, not text in ``encoding`` or unreadable."""
    label = str(path)
    try:
        return Path(path).read_text(encoding=encoding)
    except FileNotFoundError:
        raise error(f"{what} {label!r} does not exist") from None
    except IsADirectoryError:
        raise error(f"{what} {label!r} is a directory") from None
    except UnicodeDecodeError:
        raise error(f"{what} {label!r} is not UTF-8 text") from None
    except OSError as failure:
        raise error(f"{what} {label!r} cannot be read: {failure.strerror or failure}") from None
