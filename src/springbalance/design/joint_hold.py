r"""A design that carries a weighted joint worse than the bare arm, solved again with the joints held.

A design of least RMS (or peak) may balance one joint at the cost of another: a spring across two joints
lowers the shoulder's torque and raises the elbow's peak above what gravity alone puts on it
(:mod:`springbalance.design.worse_joints`). The command refuses such a design on a joint of weight > 0
(``worse_joint``, exit 3). :func:`held_within_bare_arm` solves it again from itself with the rows of
``no_joint_worse`` (docs/model.md §7),

.. math::
    \frac{P_j^2 - \tau_{ij}^2}{P_j} \ge 0 \quad \text{at every sample } i \text{ and weighted joint } j,

``P_j`` the bare arm's peak ``max_i |g_ij|`` [N·m or N], the rounded wires held: the nearest design, by a local
solve, whose every weighted joint stays within the bare arm's peak. The design returned belongs to the problem
as given (without those rows), so its objective is the user's; it is kept only when it makes no weighted joint
worse. On bench_real's ur5-mounted-coils-clear, seeds 2 and 4 made the elbow's peak worse (15.9 N·m on the bare
arm); held, they cost 4.122 → 4.361 and 4.1667 → 4.1679 N·m, and both pass.
"""

from __future__ import annotations

import dataclasses
import time
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from springbalance.design.objectives import percent_change
from springbalance.design.solvers import Solution, solve_problem
from springbalance.design.worse_joints import weighted_joints_made_worse
from springbalance.errors import SolverError

if TYPE_CHECKING:
    from springbalance.design.problem import DesignProblem


@dataclasses.dataclass(frozen=True)
class JointHold:
    """What holding the joints did.

    Attributes:
        joints: the weighted joints the design carried worse than the bare arm.
        objective_before: the design's objective before (the problem's unit).
        objective: the objective of the held design (``objective_before`` when none was kept).
        held: whether a held design was found and kept (it makes no weighted joint worse).
        seconds: the time the held solve took [s].
    """

    joints: list[str]
    objective_before: float
    objective: float
    held: bool
    seconds: float

    @property
    def cost_percent(self) -> float:
        """How much worse the objective got [%]."""
        return percent_change(self.objective_before, self.objective)

    def to_dict(self) -> dict[str, Any]:
        """The record as JSON-ready values (``design.json``'s ``solver.joint_hold``)."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, record: Any) -> JointHold | None:
        """The record a saved design carries (None when it has none or it is damaged)."""
        if not isinstance(record, dict):
            return None
        try:
            return cls(
                [str(name) for name in record["joints"]],
                float(record["objective_before"]),
                float(record["objective"]),
                bool(record["held"]),
                float(record.get("seconds", 0.0)),
            )
        except (KeyError, TypeError, ValueError):
            return None


def held_within_bare_arm(
    problem: DesignProblem, solution: Solution, fixed: Sequence[str] = (), **solve_options: Any
) -> tuple[Solution, JointHold | None]:
    """``solution`` of ``problem`` when it makes no weighted joint worse (or the problem holds its joints already:
    ``no_joint_worse``), with None; else the design solved again from it with every weighted joint held (see the
    module), ``fixed`` design variables held at their values (the rounded wires), and the :class:`JointHold`.
    ``solve_options`` go to :func:`~springbalance.design.solvers.solve_problem`. The held design's status names
    the joints and ends with its solve's own status."""
    if problem.no_joint_worse:
        return solution, None
    x = np.asarray(solution.x, dtype=float)
    worse = weighted_joints_made_worse(problem, x)
    if not worse:
        return solution, None
    clock = time.perf_counter()
    before = problem.objective_at(x)
    held_problem = problem.with_springs(problem.springs, no_joint_worse=True)
    try:
        found = solve_problem(held_problem, starts=1, initial=x, fixed=list(fixed), progress=False, **solve_options)
    except SolverError:  # (no design near this one holds the joints: it stays, and fails as it did)
        found = None
    if found is None or weighted_joints_made_worse(problem, np.asarray(found.x, dtype=float)):
        return solution, JointHold(worse, before, before, False, time.perf_counter() - clock)
    held_x = np.asarray(found.x, dtype=float)
    status = f"{solution.status}; solved again with {', '.join(worse)} held within the bare arm's peak: {found.status}"
    # the held problem's multipliers belong to its own rows, not to the problem's: none are kept
    held = Solution(held_x, solution.starts, solution.method, solution.seed, status)
    return held, JointHold(worse, before, problem.objective_at(held_x), True, time.perf_counter() - clock)
