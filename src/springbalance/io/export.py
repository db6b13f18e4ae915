"""What the URDF and MuJoCo exports share: the report, anchor names, exact numbers, the source URDF.

:mod:`springbalance.io.urdf` writes the URDF with anchor links and spring records;
:mod:`springbalance.io.mjcf` writes the MuJoCo model.
"""


from __future__ import annotations

import dataclasses
from pathlib import Path

from springbalance.errors import InputError

GROUND = "universe"


@dataclasses.dataclass
class ExportReport:
    """What an export wrote, and what it could not express exactly.

    Attributes:
        path: the file written.
        files: every file written (the URDF's sidecar JSON too).
        warnings: springs whose real law differs from the exported one somewhere in the
            workspace (slack, beyond the stroke, ...), and things left out (mesh formats).
    """

    path: Path
    files: list[Path]
    warnings: list[str]


def _source_urdf(result):
    """(XML text, folder of the file or None) of the design's mechanism."""
    source = result.problem.mechanism.source
    kind = source.get("kind")
    if kind in ("urdf", "robot"):
        path = Path(source["path"])
        try:
            return path.read_text(), path.parent
        except OSError as error:
            raise InputError(f"cannot read the URDF {str(path)!r} of the design: {error.strerror}") from None
    if kind == "urdf_string":
        return source["text"], None
    raise InputError(f"cannot export a mechanism built from a {kind!r} source: it has no URDF")


def _number(value: float) -> str:
    """Shortest text that reads back as exactly ``value``."""
    return repr(float(value))


def _vector(values) -> str:
    return " ".join(_number(v) for v in values)


def anchor_link_name(spring: str, end: str) -> str:
    """Name of the URDF link (and MuJoCo site) of end ``end`` of spring ``spring``."""
    return f"{spring}_anchor_{end}"


def _resolve_package(filename: str, directories) -> Path | None:
    relative = filename[len("package://"):]
    for directory in directories:
        candidate = Path(directory) / relative
        if candidate.is_file():
            return candidate
        package, _, rest = relative.partition("/")
        candidate = Path(directory) / rest
        if rest and candidate.is_file():
            return candidate
    return None


def law_warnings(result) -> list[str]:
    """Springs whose real law differs from the idealised two-sided law somewhere in the workspace.

    springbalance and MuJoCo both evaluate each law as written in docs/model.md §3 at every
    length; a physical spring does not (an extension spring below its free length goes slack, a
    gas spring stops at its extended length, ...). Each law says where it departs
    (:meth:`~springbalance.springs.laws.base.TwoPointSpring.law_warnings`); each case found at a
    workspace sample is one message.
    """
    evaluation = result.evaluation
    warnings = []
    for column, (spring, record) in enumerate(zip(result.problem.springs, result.springs)):
        if spring.anchors:
            warnings.extend(spring.law_warnings(record, evaluation.lengths[:, column]))
    return warnings
