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
