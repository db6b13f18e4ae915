r"""The design problem: mechanism + workspace + springs + objective → an inspectable NLP.

``springbalance.solve(DesignProblem(mechanism, workspace, springs, objective="rms"), starts=8)`` is the
one-line use. The problem holds the data and evaluates a design; no step of the solve writes into it
(:meth:`DesignProblem.with_linear_rows` makes the copy a step needs). What the solvers see, the scaled
variables and the NLP of :meth:`DesignProblem.build`, is :class:`~springbalance.design.problem_nlp.ProblemNlp`.
Solutions and reports are always in physical units.

Scenarios (payloads, scaled link masses; :mod:`springbalance.design.scenarios`): with ``scenarios=[...]``
the workspace is stacked once per scenario and ``per_scenario=[...]`` names the variables that
take one value per scenario (``s1.b`` → ``s1.b.s[<scenario>]``); the others are shared.

``no_joint_worse=True`` adds constraint rows that keep every weighted joint's residual torque within
its unbalanced peak (:attr:`DesignProblem.joint_limits`, docs/model.md §6): no joint ends up
worse than without springs, whatever the objective trades. ``max_spring_mass`` [kg] adds one row that
bounds the springs' total mass (docs/model.md §5.1).
"""

from __future__ import annotations

import copy
import dataclasses
from typing import Any, Mapping, Sequence

import numpy as np
import numpy.typing as npt

from springbalance.design.block_kernel import KERNEL_MIN_SAMPLES
from springbalance.design.bounds import check_cable
from springbalance.design.clearance import Clearance, LinearRows
from springbalance.design.evaluation import Evaluation, row_units
from springbalance.design.mounts import check_mounts, resolve_mounts
from springbalance.design.objectives import Objective, ScenarioAggregate
from springbalance.design.problem_deprecated import DeprecatedProblemMethods
from springbalance.design.problem_inputs import (
    AGGREGATES,
    joint_limits,
    joint_weights,
    named_springs,
    problem_objective,
    spring_mass_bound,
)
from springbalance.design.problem_nlp import ProblemNlp
from springbalance.design.problem_record import options, options_record, scenario_rows
from springbalance.design.robust import case_scenarios, checked_tolerance, robust_cases
from springbalance.design.scenarios import Scenario, ScenarioWorkspace, check_scenarios
from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.design.torque_model import BlockEvaluator, TorqueModel, compiled
from springbalance.errors import InputError
from springbalance.model import budget
from springbalance.model.kinematics import WorkspaceKinematics
from springbalance.model.mechanism import Mechanism
from springbalance.model.workspace import Workspace
from springbalance.springs.laws import Spring, TwoPointSpring
from springbalance.springs.records import spring_from_dict


class DesignProblem(ProblemNlp, DeprecatedProblemMethods):
    """Choose spring parameters so that the actuators carry as little gravity torque as possible.

    Args:
        mechanism: the arm.
        workspace: samples over which the design is judged (of ``mechanism``).
        springs: spring objects; unnamed ones are called ``s1``, ``s2``, … in order.
        objective: ``"rms"``, ``"peak"``, ``"pe_variance"``, ``"energy"`` (ordered workspace),
            ``"joint_peaks"`` (sum of the per-joint weighted peaks) or ``"peak_then_joints"`` (the
            worst joint first, then the sum of the joint peaks), or an
            :class:`~springbalance.design.objectives.Objective` such as ``PeakThenJoints(slack=0.01)``.
        weights: per-joint weights ``w_j`` (joint name → weight ≥ 0); default 1 for every joint.
        scenarios: optional load cases (:class:`~springbalance.design.scenarios.Scenario`: payloads,
            scaled link masses). The problem then covers every scenario over the same poses:
            its :attr:`workspace` is the given one stacked once per scenario (``N·S`` samples,
            block ``s`` = scenario ``s``), and :attr:`base_workspace` the given one.
        per_scenario: design variables that take one value per scenario (an adjustable anchor,
            a preload): names or prefixes of names, e.g. ``"s1.b"`` for every coordinate of
            spring s1's end b. They become ``<name>[<scenario>]``; every other variable is shared.
        aggregate: how the objective combines scenarios: ``"sum"`` (the objective over all
            stacked samples: the sum of squares for ``rms``, the largest torque for ``peak``) or
            ``"worst"`` (the largest per-scenario value, an epigraph solved with IPOPT).
        no_joint_worse: add constraint rows ``|tau_ij| ≤ P_j`` at every sample ``i`` and every joint
            ``j`` with a weight > 0, ``P_j`` being that joint's unbalanced peak ``max_i |g_ij|`` over
            the workspace (per scenario with scenarios), floored at ``1e-6`` of the largest
            (:attr:`joint_limits`), or the bare arm's ``|g_ij|`` at a pose where that is larger (the
            verification's unseen poses): no joint ends up worse than without springs. Both solver methods
            respect them (least squares through its augmented Lagrangian, IPOPT as rows).
        clearance: a :class:`~springbalance.design.clearance.Clearance` (margin [m], check poses):
            every two-point spring keeps that distance from the arm's collision geometry (and,
            optionally, from the other springs) over the workspace. :meth:`solve` enforces it with
            linearised rows (:attr:`linear_rows`), refreshed until a check finds no violation.
            Anchors mounted ``on: collision`` are enforced the same way, with or without it.
        max_spring_mass: an upper bound [kg] on the total mass of the springs, a constraint row of the
            design (:func:`springbalance.design.spring_mass.total_spring_mass`: a coil's wire, a
            given ``mass``; an ideal spring without one counts 0). None: no bound.
        tolerance: the springs' tolerances (:class:`~springbalance.design.tolerance_spec.ToleranceSpec`); with
            ``robust`` the problem's scenarios are the nominal law and the corners of the box, its objective
            the worst of them (:mod:`springbalance.design.robust`, docs/model.md §3.10).
    """

    def __init__(
        self,
        mechanism: Mechanism,
        workspace: Workspace,
        springs: Sequence[Spring],
        objective: str | Objective = "rms",
        weights: Mapping[str, float] | None = None,
        scenarios: Sequence[Scenario] | None = None,
        per_scenario: Sequence[str] = (),
        aggregate: str = "sum",
        no_joint_worse: bool = False,
        clearance: Clearance | None = None,
        max_spring_mass: float | None = None,
        tolerance: ToleranceSpec | None = None,
    ):
        if workspace.mechanism is not mechanism:
            raise InputError(
                "the workspace was sampled for a different mechanism object; build it from the same Mechanism"
            )
        if aggregate not in AGGREGATES:
            raise InputError(f"unknown scenario aggregate {aggregate!r}; valid: {', '.join(AGGREGATES)}")
        self.base_workspace = workspace
        self.springs = resolve_mounts(mechanism, named_springs(springs))
        self.tolerance = checked_tolerance(tolerance)
        #: the corner cases of a robust design (they are its scenarios), or None
        self.corners = robust_cases(self.tolerance, self.springs, objective, scenarios, per_scenario)
        scenarios = case_scenarios(self.corners) if self.corners is not None else scenarios
        self.scenarios = check_scenarios(mechanism, scenarios) if scenarios is not None else []
        self.per_scenario = [str(name) for name in per_scenario]
        self.aggregate = aggregate if self.corners is None else "worst"
        if self.scenarios:
            workspace = ScenarioWorkspace(workspace, self.scenarios)
        self.mechanism, self.workspace = mechanism, workspace
        combined = "worst" if self.corners is not None else aggregate
        self.objective = problem_objective(objective, workspace, len(self.scenarios), combined)
        self.weights = joint_weights(mechanism, weights)
        nv, nq, samples = mechanism.nv, mechanism.model.nq, workspace.size
        budget.require(budget.kinematics_bytes(samples, nv, nq), f"the gravity torques of {samples} samples")
        kinematics = workspace.kinematics()
        self.no_joint_worse = bool(no_joint_worse)
        self.max_spring_mass = spring_mass_bound(max_spring_mass)  # [kg] or None
        self.joint_limits = joint_limits(kinematics.gravity_torque, self.weights, max(len(self.scenarios), 1))
        self.model = self._torque_model()
        self.data = self.model.data_matrix(kinematics)
        self.path_steps = self._path_steps()
        self.torque_scale, self.potential_scale = self._scales(kinematics)
        # what the evaluation and the solvers compile, kept across solves and shared with the copies
        # that carry other linear rows (:meth:`with_linear_rows`): it depends on the samples only
        self._compiled = _Compiled()
        #: rows ``G x + h ≥ 0`` affine in the design variables (clearance and mounting cuts), or None
        self.linear_rows: LinearRows | None = None
        if clearance is not None and not isinstance(clearance, Clearance):
            raise InputError(f"clearance must be a springbalance.Clearance, got {type(clearance).__name__}")
        self.clearance = clearance
        self._check_springs()
        self.mounts = check_mounts(mechanism, self.springs)

    def _torque_model(self) -> TorqueModel:
        """The per-sample model of the springs, within the memory budget of its evaluation."""
        mechanism, samples = self.mechanism, self.workspace.size
        nv, nq = mechanism.nv, mechanism.model.nq
        model = TorqueModel(
            mechanism,
            self.springs,
            [s.name for s in self.scenarios],
            self.per_scenario,
            joint_limits=self.joint_limits if self.no_joint_worse else None,
            max_spring_mass=self.max_spring_mass,
            corners=self.corners,
        )
        budget.require(
            budget.evaluation_bytes(
                samples,
                nv,
                nq,
                model.data_size,
                nv + 1 + 2 * model.n_springs + model.n_constraints,
                model.variables.size,
                model.n_constraints,
            ),
            f"a design problem of {samples} samples, {model.n_springs} springs and {model.variables.size} variables",
        )
        return model

    def _path_steps(self) -> np.ndarray | None:
        """``|q_{i+1} - q_i|`` (N-1 × nv) [rad or m] of an ordered workspace, none across scenario blocks."""
        workspace = self.workspace
        if not workspace.ordered or workspace.size <= 1:
            return None
        steps = np.abs(np.diff(workspace.joint_values, axis=0))
        if self.scenarios:
            block = self.base_workspace.size
            steps[block - 1 :: block] = 0.0  # no step from one scenario's last pose to the next one's first
        return steps

    def _scales(self, kinematics: WorkspaceKinematics) -> tuple[float, float]:
        """``(S, σ_V)``: the RMS of the unbalanced weighted gravity torque [N·m] and the standard deviation of
        the unbalanced potential [J] (1 where zero), the solvers' units of torque and of potential."""
        gravity = kinematics.gravity_torque * self.weights
        return float(np.sqrt(np.mean(gravity**2))) or 1.0, float(np.std(kinematics.potential)) or 1.0

    # ---------------------------------------------------------------- numeric evaluation
    def evaluate(self, x: npt.ArrayLike | None = None) -> Evaluation:
        """Residual torque, potential, lengths, tensions and constraint rows of design ``x``."""
        x = np.array(self.variables.start if x is None else x, dtype=float)
        if x.shape != (self.variables.size,):
            raise InputError(
                f"design vector has {x.size} entries, problem has {self.variables.size}: "
                f"{', '.join(self.variables.names)}"
            )
        cache = self._compiled
        if cache.evaluator is None:  # block by block: no work arrays for all samples at once
            cache.evaluator = BlockEvaluator(self.sample_function(), self.data)
            cache.row_units = row_units(self.model.constraint_blocks)
        tau, potential, lengths, tensions, rows = cache.evaluator.evaluate(x)
        n = self.workspace.size
        tau, lengths, tensions, rows = (array.reshape(n, -1) for array in (tau, lengths, tensions, rows))
        return Evaluation(x, tau, potential.reshape(n), lengths, tensions, rows, cache.row_units)

    def sample_function(self) -> Any:
        """The model's per-sample function, compiled to C (with its block kernel) for a workspace of
        :data:`~springbalance.design.block_kernel.KERNEL_MIN_SAMPLES` samples or more, where the virtual machine
        takes seconds; made once per problem."""
        cache = self._compiled
        if cache.sample is None:
            cache.sample = (
                compiled(self.model.sample) if self.workspace.size >= KERNEL_MIN_SAMPLES else self.model.sample
            )
        return cache.sample

    def with_linear_rows(self, rows: LinearRows | None) -> DesignProblem:
        """This problem with other :attr:`linear_rows` (this one is not changed). The copy shares the
        data and the compiled evaluation and residuals: only the rows differ."""
        problem = copy.copy(self)
        problem.linear_rows = rows
        return problem

    @property
    def least_squares_cache(self) -> Any:
        """The solvers' compiled least-squares residuals of these samples (None before the first solve),
        bound to this problem (and so to its linear rows)."""
        cached = self._compiled.least_squares
        if cached is not None and cached.problem is not self:
            cached = cached.for_problem(self)  # the same compiled functions, read with this problem's rows
        return cached

    @least_squares_cache.setter
    def least_squares_cache(self, residuals: Any) -> None:
        self._compiled.least_squares = residuals

    @property
    def nlp_cache(self) -> dict:
        """The solvers' NLPs, per objective phase, each with the linear rows it was built for."""
        return self._compiled.nlps

    def objective_value(self, evaluation: Evaluation) -> float:
        """The objective [its unit] of an evaluation of this problem (weighted torques, potentials, path steps)."""
        return self.objective.value(evaluation.tau * self.weights, evaluation.potential, self.path_steps)

    def objective_at(self, x: npt.ArrayLike) -> float:
        """The objective [its unit] of design ``x`` (physical units) over the problem's samples."""
        return float(self.objective_value(self.evaluate(np.asarray(x, dtype=float))))

    # ---------------------------------------------------------------- scenarios
    def scenario_springs(self, x: np.ndarray, scenario: int = 0) -> list[Spring]:
        """The springs with every variable fixed at its value in ``scenario`` (design ``x``)."""
        records = []
        for spring in self.springs:
            values = self.model.spring_values(spring, x, scenario)
            record = {**spring.to_dict(), **{key: values[key] for key in spring.parameter_units}}
            for end, anchor in spring.anchors.items():
                record[end] = {"body": anchor.body, "point": self.model.anchor_point(spring, end, x, scenario).tolist()}
            records.append(spring_from_dict(record))
        return records

    def scenario_problem(
        self, scenario: int, springs: Sequence[Spring] | None = None, objective: str | Objective | None = None
    ) -> DesignProblem:
        """A single-scenario problem: scenario ``scenario``'s mechanism on :attr:`base_workspace`.

        ``springs`` default to this problem's springs (with their free variables).
        """
        # the workspace is a ScenarioWorkspace exactly when there are scenarios
        workspace = self.workspace
        mechanism = workspace.mechanisms[scenario] if isinstance(workspace, ScenarioWorkspace) else self.mechanism
        workspace = Workspace(
            mechanism,
            self.base_workspace.joint_values,
            ordered=self.base_workspace.ordered,
            description=self.base_workspace.description,
        )
        if objective is None:
            objective = self.objective.inner if isinstance(self.objective, ScenarioAggregate) else self.objective
        return DesignProblem(
            mechanism,
            workspace,
            list(springs if springs is not None else self.springs),
            objective=objective,
            weights=self.weights_by_name(),
            no_joint_worse=self.no_joint_worse,
        )

    def scenarios_record(self) -> dict:
        """The problem's options beyond objective and weights, for a saved design
        (:func:`~springbalance.design.problem_record.options_record`)."""
        robust = self.tolerance if self.corners is not None else None
        scenarios = self.scenarios if robust is None else []
        return options_record(
            scenarios,
            self.per_scenario,
            self.aggregate,
            self.no_joint_worse,
            self.max_spring_mass,
            self.clearance,
            robust,
        )

    @staticmethod
    def scenario_options(record: dict) -> dict:
        """Keyword arguments from a saved design's record (:func:`~springbalance.design.problem_record.options`)."""
        return options(record)

    def scenario_table(self, x: np.ndarray) -> list[dict]:
        """Per scenario: name, payload [kg], per-scenario variable values, peak and RMS residual [N·m]
        (weighted, over all joints) of design ``x`` (:func:`~springbalance.design.problem_record.scenario_rows`)."""
        return scenario_rows(self, x)

    def with_springs(self, springs: Sequence[Spring], **changes: Any) -> DesignProblem:
        """The same problem (mechanism, poses, objective, weights, scenarios) with other springs.

        ``changes`` override keyword arguments of :class:`DesignProblem` (``objective``,
        ``per_scenario``, ``no_joint_worse``, ...). The objective is the problem's own, before it was
        combined over scenarios.
        """
        return self._rebuilt(self.base_workspace, springs, **changes)

    def with_samples(self, joint_values: npt.ArrayLike) -> DesignProblem:
        """This problem with the poses ``joint_values`` (M×nv) [rad or m] added after its workspace's
        samples (this one is not changed): a new problem, with its own evaluation and compiled functions
        (they depend on the samples), the same springs, options and linear rows. The added poses enter
        every constraint row and the objective; in an ordered workspace they take no path step, so a
        path objective (``energy``) does not see them. ``no_joint_worse`` limits are the unbalanced peaks
        over all samples, the added ones included."""
        base, added = self.base_workspace, np.atleast_2d(np.asarray(joint_values, dtype=float))
        values = np.vstack([base.joint_values, added])
        description = {**base.description, "added_samples": int(added.shape[0])}
        problem = self._rebuilt(Workspace(self.mechanism, values, ordered=base.ordered, description=description))
        if problem.path_steps is not None:  # no step into, between or out of the added poses (per scenario block)
            for first in range(base.size - 1, problem.path_steps.shape[0], values.shape[0]):
                problem.path_steps[first : first + added.shape[0]] = 0.0
        return problem

    def _rebuilt(self, workspace: Workspace, springs: Sequence[Spring] | None = None, **changes: Any) -> DesignProblem:
        """A new problem of ``workspace`` (base poses) and ``springs`` (default this one's), with this one's
        options overridden by ``changes``, and its linear rows."""
        objective = self.objective.inner if isinstance(self.objective, ScenarioAggregate) else self.objective
        options = {
            "objective": objective,
            "weights": self.weights_by_name(),
            "scenarios": (self.scenarios or None) if self.corners is None else None,
            "per_scenario": self.per_scenario,
            "aggregate": self.aggregate,
            "no_joint_worse": self.no_joint_worse,
            "clearance": self.clearance,
            "max_spring_mass": self.max_spring_mass,
            "tolerance": self.tolerance,
            **changes,
        }
        springs = self.springs if springs is None else springs
        return type(self)(self.mechanism, workspace, list(springs), **options).with_linear_rows(self.linear_rows)

    def weights_by_name(self) -> dict[str, float]:
        return {joint.name: float(w) for joint, w in zip(self.mechanism.joints, self.weights)}

    # ---------------------------------------------------------------- checks
    def _check_springs(self) -> None:
        # Each spring checked its own bodies and joints when the torque model was built
        # (Spring.check); what needs an evaluation is a two-point spring of zero length, and a
        # routed spring's cable that is longer than its path can ever be.
        for spring in self.springs:
            if isinstance(spring, TwoPointSpring) and spring.routed:  # only a two-point spring is routed
                check_cable(self, spring)
        for column, spring in enumerate(self.springs):
            anchors = list(spring.anchors.values())
            if len(anchors) == 2 and not any(anchor.is_free for anchor in anchors):
                evaluation = self.evaluate()
                shortest = float(np.min(evaluation.lengths[:, column]))
                if shortest < 1e-9:
                    sample = int(np.argmin(evaluation.lengths[:, column]))
                    raise InputError(
                        f"spring {spring.name!r}: its ends coincide (zero length) at workspace sample {sample}"
                    )

    def __repr__(self) -> str:
        return (
            f"DesignProblem({self.mechanism.name!r}, N={self.workspace.size}, springs={len(self.springs)}, "
            f"variables={self.variables.size}, objective={self.objective.name!r})"
        )


@dataclasses.dataclass
class _Compiled:
    """What a problem compiles once for its samples: the per-sample function, the block evaluator, its rows'
    units, the least-squares residuals and the NLPs (by objective phase, with the linear rows each was built for)."""

    sample: Any = None
    evaluator: BlockEvaluator | None = None
    row_units: np.ndarray | None = None  # Evaluation.row_units, with the evaluator
    least_squares: Any = None
    nlps: dict = dataclasses.field(default_factory=dict)
