"""What the URDF and MuJoCo exports share: the report, anchor names, exact numbers, the source URDF.

:mod:`springbalance.export.urdf` writes the URDF with anchor links and spring records;
:mod:`springbalance.export.mjcf` writes the MuJoCo model. Both read a design's numbers
(:class:`~springbalance.design.evaluated.EvaluatedDesign`: its problem, spring records and
evaluation), never the result object of :mod:`springbalance.results`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable
from pathlib import Path

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.errors import InputError
from springbalance.model.mechanism import Mechanism
from springbalance.model.pseudo_bases import add_pseudo_bases
from springbalance.springs.laws.spring import Spring

__all__ = [
    "GROUND",
    "ExportReport",
    "anchor_link_name",
    "law_warnings",
    "number",
    "resolve_package",
    "source_urdf",
    "spring_name",
    "vector",
]

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


def source_urdf(mechanism: Mechanism) -> tuple[str, Path | None]:
    """(XML text, folder of the file or None) of the URDF ``mechanism`` was built from, with the mimic chains of
    its pseudo-bases (:func:`~springbalance.model.pseudo_bases.add_pseudo_bases`) when it has any."""
    source = mechanism.source
    kind = source.get("kind")
    if kind in ("urdf", "robot"):
        path = Path(source["path"])
        try:
            text, folder = path.read_text(), path.parent
        except OSError as error:
            raise InputError(f"cannot read the URDF {str(path)!r} of the design: {error.strerror}") from None
    elif kind == "urdf_string":
        text, folder = source["text"], None
    else:
        raise InputError(f"cannot export a mechanism built from a {kind!r} source: it has no URDF")
    return add_pseudo_bases(text, mechanism.pseudo_bases), folder


def number(value: float) -> str:
    """Shortest text that reads back as exactly ``value``."""
    return repr(float(value))


def vector(values: Iterable[float]) -> str:
    """The numbers of ``values`` separated by spaces, each as :func:`number` writes it."""
    return " ".join(number(v) for v in values)


def spring_name(spring: Spring) -> str:
    """The name of a spring of a design (a DesignProblem names every spring, ``s0``, ``s1``, ... when not given).

    Raises:
        InputError: ``spring`` has no name (it is not a spring of a DesignProblem).
    """
    if spring.name is None:
        raise InputError(f"a {spring.kind} spring of the design has no name")
    return spring.name


def anchor_link_name(spring: str, end: str) -> str:
    """Name of the URDF link (and MuJoCo site) of end ``end`` of spring ``spring``."""
    return f"{spring}_anchor_{end}"


def resolve_package(filename: str, directories: Iterable[str | Path]) -> Path | None:
    """The file a ``package://<package>/<path>`` mesh name stands for: ``<directory>/<package>/<path>`` or
    ``<directory>/<path>`` of the first of ``directories`` that has it (None when none has)."""
    relative = filename[len("package://") :]
    for directory in directories:
        candidate = Path(directory) / relative
        if candidate.is_file():
            return candidate
        package, _, rest = relative.partition("/")
        candidate = Path(directory) / rest
        if rest and candidate.is_file():
            return candidate
    return None


def law_warnings(design: EvaluatedDesign) -> list[str]:
    """Springs whose real law differs from the idealised two-sided law somewhere in the workspace.

    springbalance and MuJoCo both evaluate each law as written in docs/model.md §3 at every
    length; a physical spring does not (an extension spring below its free length goes slack, a
    gas spring stops at its extended length, ...). Each law says where it departs
    (:meth:`~springbalance.springs.laws.base.TwoPointSpring.law_warnings`); each case found at a
    workspace sample is one message.
    """
    evaluation = design.evaluation
    warnings = []
    for column, (spring, record) in enumerate(zip(design.problem.springs, design.springs)):
        if spring.anchors:
            warnings.extend(spring.law_warnings(record, evaluation.lengths[:, column]))
    return warnings
