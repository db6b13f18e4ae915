"""Output files written whole or not at all.

Every file springbalance writes (designs, exports, scenes, reports) goes through a temporary
file in the same folder that is renamed over the target, so a failure never leaves a
half-written file, and an existing file stays untouched until the new one is complete.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path``; folders are created; permissions follow the umask."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.fchmod(handle, 0o666 & ~umask)
        with os.fdopen(handle, "w", encoding="utf-8") as stream:
            stream.write(text)
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise
    return path


def write_json_atomic(path: str | Path, record: dict) -> Path:
    """Write ``record`` as indented JSON (floats round-trip exactly) to ``path``."""
    return write_text_atomic(path, json.dumps(record, indent=1, allow_nan=True) + "\n")


def read_input_text(
    path: str | Path, what: str, error: type[Exception], encoding: str = "utf-8", max_bytes: int | None = None
) -> str:
    """The text of the input file ``path`` (a config, URDF, catalogue, design); raises ``error`` (one line
    naming ``what``, e.g. "config file", and the path) when the file is missing, a directory, not text in
    ``encoding``, unreadable (permission denied) or larger than ``max_bytes`` [bytes] (None: any size), and when
    ``path`` holds a NUL byte (no file can have that name; the OS would raise ValueError)."""
    label = str(path)
    if "\0" in label:
        raise error(f"{what} {label!r} is not a valid path: it contains a NUL byte")
    try:
        if max_bytes is None:
            data = Path(path).read_bytes()
        else:
            with open(path, "rb") as stream:
                data = stream.read(max_bytes + 1)
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
