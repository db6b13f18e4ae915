"""One finding about a design (:class:`Flag`) and its two severities.

A **failure** means the design must not pass as fine: it breaks a constraint, the solver did not
finish, a coil cannot be wound, a spring overlaps the arm, a joint asked to be balanced carries more
torque than without springs. ``springbalance design`` then exits with status 3 and saves nothing
unless ``--partial`` is given. A **warning** points something out (a variable at its bound, a weak
design, a workspace beyond the joint limits, ...); the exit status is unchanged. The checks that find
them are listed in :mod:`springbalance.results.flags`.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Iterable

#: a finding that makes the design fail (the command line's exit status 3)
FAILURE = "failure"
#: a finding a report points out; the design still passes
WARNING = "warning"
SEVERITIES = (FAILURE, WARNING)


@dataclasses.dataclass(frozen=True)
class Flag:
    """One finding about a design.

    Attributes:
        kind: what was checked (see :mod:`springbalance.results.flags` for the kinds).
        subject: what it is about: a design variable, a joint, a spring name, or ``design``.
        message: what was found, with the numbers.
        hint: what to change, or None.
        severity: ``"failure"`` (the design does not pass) or ``"warning"`` (default).
    """

    kind: str
    subject: str
    message: str
    hint: str | None = None
    severity: str = WARNING

    def __post_init__(self) -> None:
        if self.severity not in SEVERITIES:
            raise ValueError(f"severity must be one of {', '.join(SEVERITIES)}, got {self.severity!r}")

    @property
    def failure(self) -> bool:
        """True for a failure (the design does not pass)."""
        return self.severity == FAILURE

    def to_dict(self) -> dict[str, Any]:
        """``{kind, severity, subject, message, hint?}`` (the record in ``design.json``'s ``warnings``
        and, for a failure, ``failures``)."""
        record = {"kind": self.kind, "severity": self.severity, "subject": self.subject, "message": self.message}
        if self.hint:
            record["hint"] = self.hint
        return record

    def __str__(self) -> str:
        return f"[{self.kind}] {self.message}" + (f" (hint: {self.hint})" if self.hint else "")


def failures_first(found: Iterable[Flag]) -> list[Flag]:
    """``found`` with the failures first, each group in its own order."""
    found = list(found)
    return [flag for flag in found if flag.failure] + [flag for flag in found if not flag.failure]
