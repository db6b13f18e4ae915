"""What verifying a design at poses it was not optimised on found (:class:`VerificationRecord`).

The verification itself is :mod:`springbalance.design.verification`; this module holds its record, as a
design carries it (``EvaluatedDesign.verification``) and ``design.json`` saves it (``solver.verification``).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np


@dataclasses.dataclass
class RuleMargin:
    """The worst margin of one rule over the poses verified.

    Attributes:
        spring: the spring the rule belongs to (``""`` for a rule of the problem, ``no_joint_worse.<joint>``).
        rule: the rule: a constraint row of the spring's law (``body_stress``, ``hook_bending``,
            ``tension``, ``solid``, ``buckling``, …) or ``clearance``.
        unit: the unit of the margins: ``"1"`` (a stress as a fraction of its full allowable), ``"m"``,
            ``"MPa"``, the joint's torque unit for ``no_joint_worse``.
        margin: the smallest margin over the poses verified [unit]; negative where the rule is broken.
            A stress margin is measured to the full allowable (the optimisation keeps a reserve, which
            is added back), a clearance margin is the distance beyond ``Clearance.margin`` [m].
        sampled: the smallest margin over the samples the design was optimised on [unit] (None for
            the clearance, which the fit checks at poses of its own).
        pose: the joint values [rad or m] where ``margin`` occurs (joint name → value).
        scenario: the scenario in which it occurs (None without scenarios).
        passed: ``margin`` is not below −:data:`~springbalance.design.solvers.FEASIBILITY_TOLERANCE`.
    """

    spring: str
    rule: str
    unit: str
    margin: float
    sampled: float | None
    pose: dict[str, float]
    scenario: str | None
    passed: bool

    @property
    def label(self) -> str:
        """``<spring>.<rule>``, or the rule alone for a rule of the problem."""
        return f"{self.spring}.{self.rule}" if self.spring else self.rule


@dataclasses.dataclass
class JointResidual:
    """A joint's residual torque [N·m or N] over the samples optimised on and over the poses verified.

    Attributes:
        joint: the joint's name.
        unit: ``"N·m"`` or ``"N"``.
        peak: largest ``|tau|`` over the samples optimised on; ``dense_peak``: over the poses verified.
        rms: RMS of ``tau`` over the samples optimised on; ``dense_rms``: over the poses verified.
    """

    joint: str
    unit: str
    peak: float
    dense_peak: float
    rms: float
    dense_rms: float


@dataclasses.dataclass
class VerificationRecord:
    """What verifying a design at unseen poses found, and what re-solving it cost.

    Attributes:
        poses: the poses verified in the last round (each in every scenario).
        sampling: how they were drawn (Sobol seed and box, or interpolated along the path).
        rules: the worst margin of every rule that depends on the pose (:class:`RuleMargin`).
        residual: per joint, the residual torque's peak and RMS (:class:`JointResidual`).
        objective: the objective's name; ``objective_sampled`` and ``objective_dense``: its value over the
            samples and over the poses verified (a path objective is not evaluated there: None).
        residual_checked: whether the residual can fail the verification (the peak objectives).
        residual_passed: the dense value of a checked objective is at most
            :data:`~springbalance.design.verification.PEAK_EXCESS` above the sampled one (True when not checked).
        passed: every rule holds at every pose verified, and the residual passed.
        rounds: re-solves made (each added the worst poses as samples and solved again from the design).
        added_poses: poses added to the samples over all rounds.
        mode: ``"resolve"`` (a violation re-solves) or ``"report"`` (it is reported only).
        seconds: wall time of the verification and its re-solves.
    """

    poses: int
    sampling: str
    rules: list[RuleMargin]
    residual: list[JointResidual]
    objective: str
    objective_sampled: float
    objective_dense: float | None
    residual_checked: bool
    residual_passed: bool
    passed: bool
    rounds: int = 0
    added_poses: int = 0
    mode: str = "resolve"
    seconds: float = 0.0

    @property
    def violated(self) -> list[RuleMargin]:
        """The rules broken at a pose verified."""
        return [rule for rule in self.rules if not rule.passed]

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, record: Any) -> VerificationRecord | None:
        """The record a saved design carries (None when it has none or it is damaged)."""
        if not isinstance(record, dict):
            return None
        try:
            values = {field.name: record[field.name] for field in dataclasses.fields(cls) if field.name in record}
            values["rules"] = [RuleMargin(**rule) for rule in values.get("rules", [])]
            values["residual"] = [JointResidual(**row) for row in values.get("residual", [])]
            return cls(**values)
        except (TypeError, KeyError):
            return None


def finite_or_none(value: float) -> float | None:
    """``value`` as a float, or None when it is not finite (JSON has no infinity)."""
    return float(value) if np.isfinite(value) else None
