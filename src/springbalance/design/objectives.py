r"""Objectives over the workspace (docs/model.md §6), one small class each.

With ``tau_ij`` the residual torque of joint ``j`` at sample ``i`` and joint weights
``w_j``, every objective maps the weighted torques ``w_j tau_ij`` (N×nv) and the total
potential ``V_i`` (N) to a number. :meth:`Objective.value` works on NumPy arrays (metrics);
:meth:`Objective.nlp` returns the CasADi pieces for the optimiser: extra variables, the
cost and constraint rows. Objectives with ``least_squares = True`` (rms, pe_variance) are
sums of squares, which the trust-region least-squares backend of :mod:`springbalance.design.solvers` exploits.

A *lexicographic* objective (``peak_then_joints``) names a :attr:`Objective.first_phase`: the
solver minimises that first, to ``T*``, then its own NLP with the epigraph variables bounded by
``T*·(1 + slack)`` (:meth:`Objective.phase_two_bound`), and ranks the starts by
:meth:`Objective.value`, ties within ``slack`` broken by :meth:`Objective.tiebreak`.
"""

from __future__ import annotations

import abc
import dataclasses
from typing import Callable, cast

import casadi as ca
import numpy as np

from springbalance.errors import InputError


@dataclasses.dataclass
class NlpPieces:
    """What an objective adds to the NLP (all scaled, dimensionless)."""

    variables: ca.MX | None  # extra variables (epigraph), or None
    lower: np.ndarray | None
    upper: np.ndarray | None
    #: weighted_tau_numeric (N×nv) -> start values of the extra variables
    start: Callable[[np.ndarray], np.ndarray] | None
    cost: ca.MX
    rows: ca.MX | None  # ≥ 0


class Objective(abc.ABC):
    """Base: subclasses set ``name``, ``unit`` and implement ``value`` and ``nlp``."""

    # plain attributes (not ClassVar): ScenarioAggregate sets them per instance from its inner objective
    name: str = ""
    unit: str = ""
    least_squares: bool = False
    needs_path: bool = False
    #: relative tolerance of a lexicographic objective: how much of the first phase's optimum the
    #: second phase may give up (and within which starts count as tied); 0 for the others.
    slack: float = 0.0

    @property
    def first_phase(self) -> Objective | None:
        """The objective minimised first when this one is lexicographic, else None."""
        return None

    def tiebreak(self, weighted_tau: np.ndarray, potential: np.ndarray | None, path: np.ndarray | None) -> float:
        """Second criterion of a lexicographic objective (ranks starts whose values tie); NaN otherwise."""
        return float("nan")

    def phase_two_bound(self, first_value: float, torque_scale: float) -> float | None:
        """Upper bound of the scaled epigraph variables in the second phase, given the first phase's
        value ``first_value`` [N·m]; None when not lexicographic."""
        return None

    @abc.abstractmethod
    def value(self, weighted_tau: np.ndarray, potential: np.ndarray | None, path: np.ndarray | None) -> float:
        """Objective of numeric torques (N×nv), potentials (N) and path steps |Δq| ((N-1)×nv); an objective
        that does not use the potentials or the path may be given None for them."""

    @abc.abstractmethod
    def nlp(
        self,
        weighted_tau: ca.MX,
        potential: ca.MX,
        path: np.ndarray | None,
        torque_scale: float,
        potential_scale: float,
    ) -> NlpPieces:
        """CasADi cost (and epigraph) for torques (nv×N MX) and potentials (1×N MX)."""


class Rms(Objective):
    r"""Root mean square of the weighted residual torque, :math:`\sqrt{\mathrm{mean}_{ij}(w_j \tau_{ij})^2}` [N·m]."""

    name, unit, least_squares = "rms", "N·m", True

    def value(self, weighted_tau: np.ndarray, potential: np.ndarray | None, path: np.ndarray | None) -> float:
        return float(np.sqrt(np.mean(np.square(weighted_tau))))

    def nlp(
        self,
        weighted_tau: ca.MX,
        potential: ca.MX,
        path: np.ndarray | None,
        torque_scale: float,
        potential_scale: float,
    ) -> NlpPieces:
        r = ca.vec(weighted_tau) / (torque_scale * np.sqrt(weighted_tau.numel()))
        return NlpPieces(None, None, None, None, ca.sumsqr(r), None)


class Peak(Objective):
    r"""Largest weighted residual torque, :math:`\max_{ij} |w_j \tau_{ij}|` [N·m].

    In the NLP: epigraph variable ``t`` with :math:`-t \le w_j\tau_{ij} \le t`, minimise ``t``.
    """

    name, unit = "peak", "N·m"

    def value(self, weighted_tau: np.ndarray, potential: np.ndarray | None, path: np.ndarray | None) -> float:
        return float(np.max(np.abs(weighted_tau)))

    def nlp(
        self,
        weighted_tau: ca.MX,
        potential: ca.MX,
        path: np.ndarray | None,
        torque_scale: float,
        potential_scale: float,
    ) -> NlpPieces:
        t = ca.MX.sym("peak")
        scaled = ca.vec(weighted_tau) / torque_scale
        rows = ca.vertcat(t - scaled, t + scaled)

        def start(tau: np.ndarray) -> np.ndarray:
            return np.array([np.max(np.abs(tau)) / torque_scale])

        return NlpPieces(t, np.array([0.0]), np.array([np.inf]), start, t, rows)


class PotentialVariance(Objective):
    r"""Variance over the samples of the total potential :math:`V_g + \sum V_s` [J²].

    Constant total potential means perfect balance.
    """

    name, unit, least_squares = "pe_variance", "J²", True

    def value(self, weighted_tau: np.ndarray, potential: np.ndarray | None, path: np.ndarray | None) -> float:
        if potential is None:
            raise InputError("objective 'pe_variance' needs the potentials of the samples")
        return float(np.var(potential))

    def nlp(
        self,
        weighted_tau: ca.MX,
        potential: ca.MX,
        path: np.ndarray | None,
        torque_scale: float,
        potential_scale: float,
    ) -> NlpPieces:
        n = potential.numel()
        centred = potential - ca.sum2(potential) / n
        return NlpPieces(None, None, None, None, ca.sumsqr(centred) / (n * potential_scale**2), None)


class PathEnergy(Objective):
    r"""Actuator work along the ordered samples, :math:`\sum_i \sum_j |w_j \tau_{ij}|\,|q_{i+1,j} - q_{ij}|` [J].

    In the NLP: epigraph variables :math:`s_{ij} \ge |w_j\tau_{ij}|`, minimise :math:`\sum s_{ij}|\Delta q_{ij}|`.
    """

    name, unit, needs_path = "energy", "J", True

    def value(self, weighted_tau: np.ndarray, potential: np.ndarray | None, path: np.ndarray | None) -> float:
        if path is None:
            return float("nan")
        return float(np.sum(np.abs(weighted_tau[:-1]) * path))

    def nlp(
        self,
        weighted_tau: ca.MX,
        potential: ca.MX,
        path: np.ndarray | None,
        torque_scale: float,
        potential_scale: float,
    ) -> NlpPieces:
        if path is None:
            raise InputError("objective 'energy' needs the ordered path of the workspace samples")
        nv, n = weighted_tau.shape
        steps = path.T  # nv×(N-1)
        s = ca.MX.sym("abs_tau", nv * (n - 1))
        scaled = ca.vec(weighted_tau[:, : n - 1]) / torque_scale
        rows = ca.vertcat(s - scaled, s + scaled)
        weights = steps.reshape(-1, order="F")
        scale = max(float(np.sum(weights)), 1e-12)

        def start(tau: np.ndarray) -> np.ndarray:
            return np.abs(tau[:-1]).reshape(-1) / torque_scale

        return NlpPieces(
            s, np.zeros(s.numel()), np.full(s.numel(), np.inf), start, ca.dot(ca.DM(weights), s) / scale, rows
        )


class JointPeaks(Objective):
    r"""Sum over the joints of each joint's weighted peak, :math:`\sum_j \max_i |w_j \tau_{ij}|` [N·m].

    Unlike ``peak``, every joint counts: lowering a joint that is not the worst one pays off.
    In the NLP: one epigraph variable per joint, :math:`-t_j \le w_j\tau_{ij} \le t_j` at every
    sample, minimise :math:`\sum_j t_j`.
    """

    name, unit = "joint_peaks", "N·m"

    def value(self, weighted_tau: np.ndarray, potential: np.ndarray | None, path: np.ndarray | None) -> float:
        return float(np.sum(np.max(np.abs(weighted_tau), axis=0)))

    def nlp(
        self,
        weighted_tau: ca.MX,
        potential: ca.MX,
        path: np.ndarray | None,
        torque_scale: float,
        potential_scale: float,
    ) -> NlpPieces:
        nv, n = weighted_tau.shape
        t = ca.MX.sym("joint_peak", nv)
        scaled = weighted_tau / torque_scale  # nv×N
        bound = ca.repmat(t, 1, n)
        rows = ca.vertcat(ca.vec(bound - scaled), ca.vec(bound + scaled))

        def start(tau: np.ndarray) -> np.ndarray:
            return np.max(np.abs(tau), axis=0) / torque_scale

        return NlpPieces(t, np.zeros(nv), np.full(nv, np.inf), start, ca.sum1(t), rows)


class PeakThenJoints(JointPeaks):
    r"""Lexicographic minimax: the worst weighted joint peak first, then the sum of the joint peaks.

    Phase 1 minimises :math:`T = \max_{ij} |w_j \tau_{ij}|` (the ``peak`` NLP) to ``T*``; phase 2
    minimises :math:`\sum_j t_j` (the ``joint_peaks`` NLP) subject to
    :math:`t_j \le T^*(1 + \varepsilon)` for every joint, so the worst joint keeps its optimum
    (to ``ε = slack``, default 1e-3) and the other joints are lowered as far as that allows.

    :meth:`value` is the worst joint's peak ``T`` [N·m] (as ``peak``); starts whose ``T`` is
    within ``slack`` of the best are ranked by the sum of the joint peaks (:meth:`tiebreak`).
    """

    name, unit = "peak_then_joints", "N·m"

    def __init__(self, slack: float = 1e-3) -> None:
        slack = float(slack)
        if not np.isfinite(slack) or slack < 0:
            raise InputError(f"slack of objective 'peak_then_joints' must be a finite number ≥ 0, got {slack}")
        self.slack = slack

    @property
    def first_phase(self) -> Objective:
        return Peak()

    def value(self, weighted_tau: np.ndarray, potential: np.ndarray | None, path: np.ndarray | None) -> float:
        return float(np.max(np.abs(weighted_tau)))

    def tiebreak(self, weighted_tau: np.ndarray, potential: np.ndarray | None, path: np.ndarray | None) -> float:
        return JointPeaks.value(self, weighted_tau, potential, path)

    def phase_two_bound(self, first_value: float, torque_scale: float) -> float:
        return float(first_value) * (1.0 + self.slack) / torque_scale


#: objective name -> class.
OBJECTIVES: dict[str, type[Objective]] = {
    cls.name: cls for cls in (Rms, Peak, PotentialVariance, PathEnergy, JointPeaks, PeakThenJoints)
}


def objective_named(name: str | Objective) -> Objective:
    """The objective called ``name`` (``rms``, ``peak``, ``pe_variance``, ``energy``, ``joint_peaks``,
    ``peak_then_joints``), or ``name`` itself when it is an :class:`Objective`."""
    if isinstance(name, Objective):
        return name
    if name not in OBJECTIVES:
        raise InputError(f"unknown objective {name!r}; valid: {', '.join(OBJECTIVES)}")
    return OBJECTIVES[name]()


class ScenarioAggregate(Objective):
    r"""An objective over S scenario blocks of the samples: the worst block, :math:`\max_s f_s`, or
    (``worst=False``) the mean :math:`\frac1S \sum_s f_s` (used for ``pe_variance``, whose potential
    has its own constant in each scenario).

    In the NLP the worst case is an epigraph variable ``t`` with :math:`t \ge f_s` (each block's
    scaled cost), minimise ``t``; it is solved by IPOPT. The mean keeps least-squares structure.
    """

    def __init__(self, inner: Objective, blocks: int, worst: bool = True) -> None:
        if inner.needs_path:
            raise InputError(f"objective {inner.name!r} cannot be aggregated per scenario; use aggregate 'sum'")
        self.inner, self.blocks, self.worst = inner, int(blocks), bool(worst)
        self.name, self.unit = inner.name, inner.unit
        self.least_squares = inner.least_squares and not self.worst

    def _split(self, values: np.ndarray | None, axis: int) -> list[np.ndarray]:
        return np.split(np.asarray(values), self.blocks, axis=axis)

    def value(self, weighted_tau: np.ndarray, potential: np.ndarray | None, path: np.ndarray | None) -> float:
        values = [
            self.inner.value(tau, v, None) for tau, v in zip(self._split(weighted_tau, 0), self._split(potential, 0))
        ]
        return float(max(values) if self.worst else np.mean(values))

    def nlp(
        self,
        weighted_tau: ca.MX,
        potential: ca.MX,
        path: np.ndarray | None,
        torque_scale: float,
        potential_scale: float,
    ) -> NlpPieces:
        n = weighted_tau.shape[1] // self.blocks
        pieces = [
            self.inner.nlp(
                weighted_tau[:, s * n : (s + 1) * n],
                potential[:, s * n : (s + 1) * n],
                None,
                torque_scale,
                potential_scale,
            )
            for s in range(self.blocks)
        ]
        costs = [piece.cost for piece in pieces]
        if not self.worst:
            # sum() of MX is MX (typeshed types its 0 start as int)
            return NlpPieces(None, None, None, None, cast(ca.MX, sum(costs)) / self.blocks, None)
        t = ca.MX.sym("worst")
        # an inner epigraph (joint_peaks) keeps its own variables and rows, one set per block
        inner = [_epigraph(piece) for piece in pieces if piece.variables is not None]
        rows = ca.vertcat(*[piece.rows for piece in inner], *[t - cost for cost in costs])
        variables = ca.vertcat(*[piece.variables for piece in inner], t)
        lower = np.concatenate([*[piece.lower for piece in inner], [0.0]])
        upper = np.concatenate([*[piece.upper for piece in inner], [np.inf]])
        inner_start = [piece.start for piece in inner]

        def start(tau: np.ndarray) -> np.ndarray:
            blocks = self._split(tau, 0)
            if self.inner.name == "rms":
                worst = max(float(np.mean(block**2)) for block in blocks) / torque_scale**2
            elif self.inner.name == "joint_peaks":
                worst = max(self.inner.value(block, None, None) for block in blocks) / torque_scale
            else:
                worst = 1.0
            epigraph_blocks = [block for piece, block in zip(pieces, blocks) if piece.variables is not None]
            inner_starts = [piece_start(block) for piece_start, block in zip(inner_start, epigraph_blocks)]
            return np.concatenate([*inner_starts, [worst]])

        return NlpPieces(variables, lower, upper, start, t, rows)


@dataclasses.dataclass
class _Epigraph:
    """The pieces of an objective that has epigraph variables, none of them None."""

    variables: ca.MX
    lower: np.ndarray
    upper: np.ndarray
    start: Callable[[np.ndarray], np.ndarray]
    rows: ca.MX


def _epigraph(piece: NlpPieces) -> _Epigraph:
    """``piece`` with its epigraph fields checked present (an objective with variables sets them all)."""
    if (
        piece.variables is None
        or piece.lower is None
        or piece.upper is None
        or piece.start is None
        or piece.rows is None
    ):
        raise AssertionError("an objective with epigraph variables must give their bounds, start and rows")
    return _Epigraph(piece.variables, piece.lower, piece.upper, piece.start, piece.rows)


def percent_change(before: float, after: float) -> float:
    """How much worse an objective got from ``before`` to ``after`` [%] (negative: better): ``100 (after − before) /
    before``, and 0 when ``before`` ≤ 0 (nothing to compare with). What a step of the solve cost (the fit to the arm,
    the wire rounding, the joint hold)."""
    if before <= 0:
        return 0.0
    return 100.0 * (after - before) / before
