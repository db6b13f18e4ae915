"""Reading an input file (config, catalogue) with a one-line error that names it."""

from __future__ import annotations

from pathlib import Path

from springbalance.errors import InputError


def read_input_text(path: str | Path, what: str, error: type[InputError] = InputError,
                    encoding: str = "utf-8", max_bytes: int | None = None) -> str:
    """The text of ``path``; raises ``error`` naming ``what`` (e.g. "config file") and the path when the
    file is missing, a directory, not text in ``encoding``, unreadable (permission denied) or larger
    than ``max_bytes`` [bytes] (None: any size)."""
    label = str(path)
    try:
        with open(path, "rb") as stream:
            data = stream.read() if max_bytes is None else stream.read(max_bytes + 1)
    except FileNotFoundError:
        raise error(f"{what} {label!r} does not exist") from None
    except IsADirectoryError:
        raise error(f"{what} {label!r} is a directory") from None
    except PermissionError:
        raise error(f"{what} {label!r} cannot be read: permission denied") from None
    except OSError as failure:
        raise error(f"{what} {label!r} cannot be read: {failure.strerror or failure}") from None
    if max_bytes is not None and len(data) > max_bytes:
        raise error(f"{what} {label!r} is larger than {max_bytes // (1 << 20)} MiB; a {what} is a small text file")
    try:
        text = data.decode(encoding)
    except UnicodeDecodeError:
        raise error(f"{what} {label!r} is not UTF-8 text") from None
    return text.replace("\r\n", "\n").replace("\r", "\n")  # universal newlines, as text mode reads them
