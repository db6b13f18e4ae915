r"""Tolerances and the adjuster (docs/model.md §3.10): the worst residual over the springs' tolerance box,
and the adjuster travel that restores the balance.

**The box.** Each two-point extension or compression spring (not routed) has a linear law
:math:`F = F_0 + k (L - l_0)` (extension, ``F_0`` the initial tension) or
:math:`F = -(P + k (l_0 - L))` (compression, ``P`` the preload, 0 for a coil). A
:class:`ToleranceSpec` gives each law a box: ``k (1 ± ρ)``, ``F_0 ± f`` (or ``P ± f``), ``l_0 ± λ``,
from a quality grade (:func:`springbalance.springs.tolerance_grades.grade_box`: a coil's geometry) or
explicit ± (``rate`` ρ [1, a fraction], ``initial_tension`` f [N], ``free_length`` λ [m]).

**Worst case without enumerating corners.** With the anchors fixed, spring ``s`` adds
:math:`\tau_s(q) = F_s(L_s(q))\,m_s(q)` to the residual, :math:`m_s = (J_{p_b} - J_{p_a})^T u` its
moment arm, which the law does not change. A change of the law changes the residual by
:math:`\delta\tau_s = \delta F_s\,m_s`, and :math:`\delta F_s` is multilinear in the spring's own three
deviations (the product :math:`\delta k\,\delta l_0` is the only cross term). A multilinear function
takes its extremes on a box at the box's corners, and the residual is a sum over springs of
functions of each spring's own deviations, so at each pose and joint the largest and smallest residual
over all :math:`8^n` corner combinations are

.. math:: r^\pm_j(q) = r_j(q) + \sum_s \operatorname{max/min}_{c \in \{\pm1\}^3} \delta\tau_{s,j}(q; c),

exact, with :math:`8 n` evaluations. The worst ``|r|`` is :math:`\max(r^+, -r^-)`; its peak over the
poses is the worst peak of any build; its RMS over the poses bounds the RMS of every build from above.

**The adjuster.** A preload screw (a threaded end plug or turnbuckle in series with the spring)
shortens the spring's effective free length by ``t`` [m] (positive: more deflection), the same at every
pose: :math:`\delta F = \sigma k t` (σ = +1 extension, −1 compression), so
:math:`\partial r/\partial t_s = \sigma_s k_s m_s` (nominal ``k``: the :math:`\delta k\,t` term is second
order). The screws restore the nominal design: at a corner the least-squares adjustment is
:math:`t = -A^+ W \delta r`, ``δr`` the corner's change of the residual (``A`` the columns
:math:`W \sigma_s k_s m_s`, ``W`` the joint weights; :math:`A^+` leaves out singular values below
:data:`ADJUSTER_RCOND` of the largest, so screws that act alike share the turn), and the nominal build needs
none. (Least squares on the whole residual would also "balance" the nominal design beyond the rules that bound its
optimum: turns of −3.2 to +1.9 m on the UR5 example, whose fatigue and mass rules bind.) It is linear in ``δr``, so
its extremes over the box are separable like the residual's. A spring's travel is the range
:math:`\max t_s - \min t_s` over the box.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.problem import DesignProblem
from springbalance.design.robust import corner_table, nominal_design
from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.springs.laws import Spring, TwoPointSpring
from springbalance.springs.laws.coil import HelicalCoilSpring
from springbalance.springs.tolerance_grades import grade_box

#: the 8 corners of a spring's box: signs of (rate, initial tension or preload, free length)
CORNERS = np.array(list(itertools.product((-1.0, 1.0), repeat=3)))
#: the adjusters' least squares leave out the directions of the screws whose singular value is below this
#: fraction of the largest: screws that act (almost) alike, as two coils side by side, share a turn instead of
#: cancelling each other by huge opposite turns that change the residual by nothing
ADJUSTER_RCOND = 1e-3


@dataclass(frozen=True)
class SpringBox:
    """One spring's law and its box: ``sign`` +1 extension / −1 compression; ``rate`` [N/m], ``tension``
    (initial tension or preload) [N], ``free_length`` [m]; the ± ``d_rate`` [1], ``d_tension`` [N],
    ``d_free_length`` [m]; ``source`` ("grade 2", "explicit")."""

    name: str
    column: int
    sign: float
    rate: float
    tension: float
    free_length: float
    d_rate: float
    d_tension: float
    d_free_length: float
    source: str

    def forces(self, lengths: np.ndarray, corners: np.ndarray = CORNERS) -> np.ndarray:
        """Tension [N] at ``lengths`` (N) for each corner (C×3 signs): C×N."""
        a, b, c = (corners[:, i : i + 1] for i in range(3))
        rate = self.rate * (1 + a * self.d_rate)
        tension = self.tension + b * self.d_tension
        free = self.free_length + c * self.d_free_length
        deflection = self.sign * (lengths[None, :] - free)  # extension: L − l0; compression: l0 − L
        return self.sign * (tension + rate * deflection)

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "source": self.source,
            "rate": self.d_rate,
            "initial_tension": self.d_tension,
            "free_length": self.d_free_length,
        }


def spring_box(problem: DesignProblem, x: np.ndarray, column: int, spec: ToleranceSpec) -> SpringBox | None:
    """The box of spring ``column`` of ``problem`` at design ``x``, or None for a spring without one (not an
    extension or compression law, routed, or an ideal law under a grade, which has no coil to grade)."""
    spring = problem.springs[column]
    kind = getattr(spring, "kind", None)
    if not isinstance(spring, TwoPointSpring) or spring.routed or kind not in ("extension", "compression"):
        return None
    values = problem.model.spring_values(spring, x)
    law = spring.derived_values(values) if isinstance(spring, HelicalCoilSpring) else values
    sign = 1.0 if kind == "extension" else -1.0
    rate, free = float(law["stiffness"]), float(law["free_length"])
    tension = float(law.get("initial_tension", law.get("preload", 0.0)))
    name = str(spring.name)
    if spec.explicit:
        return SpringBox(
            name, column, sign, rate, tension, free,
            spec.rate or 0.0, spec.initial_tension or 0.0, spec.free_length or 0.0, "explicit",
        )  # fmt: skip
    if not isinstance(spring, HelicalCoilSpring) or spec.grade is None:
        return None
    d, D, n = (float(values[key]) for key in ("wire_diameter", "mean_diameter", "active_coils"))
    box = grade_box(kind, d, D, n, free, rate, tension, spec.grade)
    return SpringBox(
        name, column, sign, rate, tension, free, box.rate, box.initial_tension, box.free_length, f"grade {spec.grade}"
    )


def moment_arms(problem: DesignProblem, x: np.ndarray, spring: Spring) -> np.ndarray:
    r"""``m_s(q) = (J_{p_b} - J_{p_a})^T u`` (N×nv) [m or 1] of a two-point spring over the problem's samples:
    its torque per newton of tension."""
    kinematics = problem.workspace.kinematics()
    ends = []
    for end, anchor in spring.anchors.items():
        body = kinematics.body(anchor.body)
        point = problem.model.anchor_point(spring, end, x)
        ends.append((body.points(point), body.point_jacobians(point)))
    (xa, ja), (xb, jb) = ends
    d = xb - xa
    u = d / np.linalg.norm(d, axis=1, keepdims=True)
    return np.einsum("ni,niv->nv", u, jb - ja)


@dataclass
class ToleranceAnalysis:
    """The worst case of a design over its springs' tolerance box, and the adjuster travel.

    Attributes:
        spec: the tolerances.
        boxes: the springs with a box.
        joints: per joint: ``joint``, ``unit``, nominal ``peak``/``rms`` and ``worst_peak``/``worst_rms`` (the
            envelope's), and after adjusting at every corner ``adjusted_peak``/``adjusted_rms`` [N·m or N].
        travel: per spring with a box: ``low``/``high`` adjustments [m] over the box (the nominal build's is 0)
            and ``travel`` = high − low [m].
        upper, lower: the residual's envelope over the box (N×nv) [N·m or N].
        corners: of a robust design, per case (the nominal law, then the corners it was designed for): ``name``,
            ``peak``/``rms`` [N·m] and, with adjusters, ``adjusters`` (spring → setting [m]) and ``at_bound``
            (:func:`springbalance.design.robust.corner_table`); else empty.
    """

    spec: ToleranceSpec
    boxes: list[SpringBox]
    joints: list[dict[str, Any]] = field(default_factory=list)
    travel: list[dict[str, Any]] = field(default_factory=list)
    upper: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    lower: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    corners: list[dict[str, Any]] = field(default_factory=list)

    @property
    def largest_travel(self) -> float:
        """The largest travel of any spring [m] (0 without boxes)."""
        return max((row["travel"] for row in self.travel), default=0.0)

    def to_dict(self) -> dict[str, Any]:
        return {
            "spec": self.spec.to_dict(),
            "adjuster": "preload screw: shortens the effective free length by t (t > 0: more deflection) [m]",
            "springs": [box.to_dict() for box in self.boxes],
            "joints": self.joints,
            "travel": self.travel,
            **({"corners": self.corners} if self.corners else {}),
        }


def analyse_tolerance(design: EvaluatedDesign, spec: ToleranceSpec | None = None) -> ToleranceAnalysis:
    """The worst residual over the tolerance box of ``design`` and each spring's adjuster travel (see the module).

    Of a robust design (:mod:`springbalance.design.robust`): the analysis of its nominal law, and in
    :attr:`ToleranceAnalysis.corners` each corner's residual and adjuster settings as designed."""
    spec = spec or design.tolerance or getattr(design.problem, "tolerance", None) or ToleranceSpec()
    problem, x = nominal_design(design.problem, design.x)
    if problem is design.problem:
        evaluation = design.evaluation
    else:
        evaluation = problem.evaluate(x)
    analysis = analyse(problem, x, evaluation.tau, evaluation.lengths, spec)
    analysis.corners = corner_table(design.problem, design.x)
    return analysis


def corner_deltas(problem: DesignProblem, x: np.ndarray, lengths: np.ndarray, boxes: list[SpringBox]) -> list:
    """Per box: (the 8 corners' residual changes, 8×N×nv; the adjuster's column σ k m, N×nv)."""
    out = []
    for box in boxes:
        arms = moment_arms(problem, x, problem.springs[box.column])
        lengths_s = lengths[:, box.column]
        nominal = box.forces(lengths_s, np.zeros((1, 3)))[0]
        deltas = (box.forces(lengths_s) - nominal)[:, :, None] * arms[None]
        out.append((deltas, box.sign * box.rate * arms))
    return out


def analyse(
    problem: DesignProblem, x: np.ndarray, tau: np.ndarray, lengths: np.ndarray, spec: ToleranceSpec
) -> ToleranceAnalysis:
    """:func:`analyse_tolerance` of design ``x`` of ``problem`` with residual ``tau`` (N×nv) and lengths (N×n_s)."""
    boxes = [box for column in range(len(problem.springs)) if (box := spring_box(problem, x, column, spec))]
    analysis = ToleranceAnalysis(spec, boxes)
    if not boxes:
        return analysis
    parts = corner_deltas(problem, x, lengths, boxes)
    upper = tau + sum(np.max(deltas, axis=0) for deltas, _ in parts)
    lower = tau + sum(np.min(deltas, axis=0) for deltas, _ in parts)
    weights = np.asarray(problem.weights, dtype=float)
    columns = np.stack([column.reshape(-1) for _, column in parts], axis=1)  # (N·nv)×n, unweighted
    pinv = np.linalg.pinv(columns * np.tile(weights, tau.shape[0])[:, None], rcond=ADJUSTER_RCOND)

    def adjustment(r: np.ndarray) -> np.ndarray:  # t = −A⁺ W r for residual changes (..., N, nv)
        return -np.einsum("sk,...k->...s", pinv, (r * weights).reshape(*r.shape[:-2], -1))

    def adjusted(r: np.ndarray) -> np.ndarray:  # r + Σ_s t_s a_s
        return r + (adjustment(r) @ columns.T).reshape(r.shape)

    # the screws restore the nominal design (t = 0 there): they answer a build's change of the residual only
    t_high = sum(np.max(adjustment(deltas), axis=0) for deltas, _ in parts)
    t_low = sum(np.min(adjustment(deltas), axis=0) for deltas, _ in parts)
    adjusted_upper = tau + sum(np.max(adjusted(deltas), axis=0) for deltas, _ in parts)
    adjusted_lower = tau + sum(np.min(adjusted(deltas), axis=0) for deltas, _ in parts)
    worst = np.maximum(upper, -lower)
    adjusted_worst = np.maximum(adjusted_upper, -adjusted_lower)
    for joint in problem.mechanism.joints:
        j = joint.index_v
        analysis.joints.append(
            {
                "joint": joint.name,
                "unit": joint.torque_unit,
                "peak": float(np.max(np.abs(tau[:, j]))),
                "rms": float(np.sqrt(np.mean(tau[:, j] ** 2))),
                "worst_peak": float(np.max(worst[:, j])),
                "worst_rms": float(np.sqrt(np.mean(worst[:, j] ** 2))),
                "adjusted_peak": float(np.max(adjusted_worst[:, j])),
                "adjusted_rms": float(np.sqrt(np.mean(adjusted_worst[:, j] ** 2))),
            }
        )
    for i, box in enumerate(boxes):
        analysis.travel.append(
            {
                "name": box.name,
                "low": float(t_low[i]),
                "high": float(t_high[i]),
                "travel": float(t_high[i] - t_low[i]),
            }
        )
    analysis.upper, analysis.lower = upper, lower
    return analysis
