"""A study's folder: claimed by one study (its config's fingerprint in ``study.json``), refused to another.

:func:`claim_folder` makes a folder a study's: a folder whose ``study.json`` holds another fingerprint
(another config) or that holds files but no study is refused unless ``force``, which discards the other
study's ``results/`` and ``designs/``. It then writes ``study.json`` (the fingerprint, the config and the
study's summary). :func:`finished_results` reads the results a run left (``results/<id>.json``), to resume.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

from springbalance.errors import InputError
from springbalance.files import write_json_atomic


def claim_folder(folder: Path, fingerprint: str, record: dict[str, Any], force: bool) -> None:
    """Make ``folder`` the study's whose fingerprint is ``fingerprint`` (see the module documentation);
    ``record`` is the rest of ``study.json`` (the config and the summary)."""
    marker = folder / "study.json"
    if marker.exists():
        try:
            previous = json.loads(marker.read_text(encoding="utf-8")).get("fingerprint")
        except (OSError, ValueError, AttributeError):
            previous = None
        if previous != fingerprint:
            if not force:
                raise InputError(
                    f"study folder {str(folder)!r} holds the results of a different config "
                    f"(fingerprint {previous} ≠ {fingerprint}); use another --out, or --force "
                    "to discard them"
                )
            for stale in ("results", "designs"):
                shutil.rmtree(folder / stale, ignore_errors=True)
    elif folder.exists() and any(folder.iterdir()) and not force:
        raise InputError(f"study folder {str(folder)!r} is not empty and holds no study; use another --out, or --force")
    write_json_atomic(marker, {"fingerprint": fingerprint, **record})


def finished_results(results: Path) -> dict[str, dict]:
    """The task results already in the folder ``results`` by id (``<id>.json`` whose ``id`` is ``<id>``; a damaged
    file is left out, so its task is solved again)."""
    done = {}
    for path in sorted(results.glob("*.json")):
        try:
            record = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if isinstance(record, dict) and record.get("id") == path.stem:
            done[path.stem] = record
    return done
