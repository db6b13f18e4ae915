"""A design evaluated on its problem: the numbers of a design, and nothing that draws or writes them.

:class:`EvaluatedDesign` is the design vector ``x`` of a :class:`~springbalance.design.problem.DesignProblem`
with its evaluation over the problem's workspace: the values by name, the springs with their anchors and
parameters, the residual torque ``tau(q)`` [N·m or N], and the metrics that compare it with the unbalanced
arm (gravity only) on the same samples: peak and RMS of each joint's torque and the percentage reduction,
and every objective of docs/model.md §6 before and after.

It is the one source of truth for a design's numbers. The views (text and HTML reports, flags, plots,
clearance tables, scenes, exports) are functions of it; :class:`~springbalance.results.result.DesignResult`
adds the one-line conveniences that call them, and saving and loading.
"""

from __future__ import annotations

from typing import Any, Iterable, Protocol, runtime_checkable

import numpy as np
import numpy.typing as npt

from springbalance.design.clearance import FitRecord
from springbalance.design.joint_hold import JointHold
from springbalance.design.objectives import OBJECTIVES
from springbalance.design.problem import DesignProblem, Evaluation
from springbalance.design.solvers import StartRecord
from springbalance.design.spring_mass import SpringMass, spring_mass
from springbalance.design.standard_wire import WireRounding
from springbalance.design.stock import StockSelection
from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.design.twin import TwinRecord
from springbalance.design.verification_record import VerificationRecord
from springbalance.design.worse_joints import TORQUE_TOLERANCE, torque_rows, worse_rows
from springbalance.errors import InputError
from springbalance.model.workspace import Workspace
from springbalance.springs.laws import Spring, TwoPointSpring
from springbalance.springs.mass import CoilMass
from springbalance.springs.records import spring_from_dict
from springbalance.springs.sizing import HelicalDesign, Material, size_helical_spring


@runtime_checkable
class _Coil(Protocol):
    """A coil law (helical extension or compression spring): its derived values and its data sheet."""

    def derived_values(self, values: dict) -> dict: ...

    def spec_sheet(self, values: dict, lengths: np.ndarray, forces: np.ndarray) -> dict: ...


def _named(spring: Spring) -> str:
    """The name of a problem's spring (a problem names every spring it is given)."""
    assert spring.name is not None
    return spring.name


class EvaluatedDesign:
    """A design (spring parameter values) evaluated on its problem's workspace.

    Attributes:
        problem: the :class:`~springbalance.design.problem.DesignProblem`.
        x: design vector in physical units (names in ``problem.variables.names``).
        starts: per-start records of the multi-start (empty when not optimised).
        status: the solver status of the chosen start.
        twin: what the design's ideal twin achieved (:mod:`springbalance.design.twin`), or None.
        partial: why the design was kept although it is not a finished one (saved with ``--partial``:
            interrupted, or failing a check), or None for a finished design.
        tolerance: the springs' tolerances (:class:`~springbalance.design.tolerance_spec.ToleranceSpec`), or None
            for the default (grade 2 for every coil).
    """

    def __init__(
        self,
        problem: DesignProblem,
        x: npt.ArrayLike,
        starts: Iterable[StartRecord] = (),
        method: str = "evaluate",
        seed: int | None = None,
        status: str = "evaluated",
        wire_rounding: WireRounding | None = None,
        joint_hold: JointHold | None = None,
        fit: FitRecord | None = None,
        stock: StockSelection | None = None,
        verification: VerificationRecord | None = None,
        twin: TwinRecord | None = None,
        partial: str | None = None,
        tolerance: ToleranceSpec | None = None,
    ) -> None:
        self.problem = problem
        self.x = np.asarray(x, dtype=float)
        self.starts = list(starts)
        self.method, self.seed, self.status = method, seed, status
        #: what rounding the coils' wires to standard sizes cost (None when nothing was rounded)
        self.wire_rounding = wire_rounding
        #: what holding the weighted joints within the bare arm's peaks did (None when none was carried worse)
        self.joint_hold = joint_hold
        #: what fitting the springs to the arm (clearance, mounting) did and cost (None when not asked for)
        self.fit = fit
        #: the catalogue parts chosen for the springs (None when no catalogue was given)
        self.stock = stock
        #: what verifying the design at poses it was not optimised on found (None when not verified)
        self.verification = verification
        #: what the ideal twin achieved (None when the design has no twin)
        self.twin = twin
        #: why this design was saved unfinished (``--partial``), or None
        self.partial = partial
        #: the springs' tolerances (None: grade 2 for every coil, docs/model.md §3.10)
        self.tolerance = tolerance
        self.evaluation = problem.evaluate(self.x)

    # ---------------------------------------------------------------- values
    @property
    def variables(self) -> dict[str, float]:
        """Design variable name → value (physical units)."""
        return dict(zip(self.problem.variables.names, self.x.tolist()))

    @property
    def springs(self) -> list[dict[str, Any]]:
        """Per spring: name, type, where it acts and its values.

        Two-point springs give their anchors ``a`` and ``b`` (body and body-frame point [m]);
        torsional springs their ``joint``. Then every parameter value (SI units), and for a
        spring that carries mass its ``mass`` [kg] (and, when the mass is coupled to the rate
        through the coil, the ``wire_diameter`` [m] that gives that rate).
        """
        model = self.problem.model
        records = []
        for column, spring in enumerate(self.problem.springs):
            record: dict[str, Any] = {"name": spring.name, "type": spring.kind}
            if spring.ideal is not None:
                record["ideal"] = bool(spring.ideal)
            for end, anchor, radius in zip(
                spring.anchors, spring.anchors.values(), getattr(spring, "radii", ()) or [0.0] * len(spring.anchors)
            ):
                record[end] = {"body": anchor.body, "point": model.anchor_point(spring, end, self.x).tolist()}
                if radius > 0:
                    record[end]["pulley"] = {"radius": radius}
            for joint in spring.joints:
                record["joint"] = joint
            values = model.spring_values(spring, self.x)
            record.update(values)
            part_number = getattr(spring, "part_number", None)
            if part_number is not None:
                record["part_number"] = part_number
            if isinstance(spring, _Coil):
                # a coil: the law's values it gives, and its data sheet with the buildable verdict
                record.update({key: value for key, value in spring.derived_values(values).items() if key not in record})
                record["helical"] = spring.spec_sheet(
                    values, self.evaluation.lengths[:, column], self.evaluation.tensions[:, column]
                )
            mass = spring.mass if isinstance(spring, TwoPointSpring) else None  # only a two-point spring has one
            if isinstance(spring, TwoPointSpring) and mass is not None:
                record["mass"] = float(spring.spring_mass(values))  # [kg]
                if isinstance(mass, CoilMass):
                    record["wire_diameter"] = float(mass.wire_diameter(values["stiffness"]))  # [m]
            records.append(record)
        return records

    def spring(self, name: str) -> dict[str, Any]:
        """Values of the spring called ``name``."""
        for record in self.springs:
            if record["name"] == name:
                return record
        raise InputError(f"unknown spring {name!r}; springs: {', '.join(_named(s) for s in self.problem.springs)}")

    def fixed_springs(self) -> list[Spring]:
        """The springs with every free parameter and anchor fixed at this design's values."""
        records = []
        for spring, values in zip(self.problem.springs, self.springs):
            record = spring.to_dict()
            parameters = {key: values[key] for key in spring.parameter_units}
            points = [values[end] for end in spring.anchors]
            if record.get("type") == "routed":
                record.update(
                    path=points, cable_length=parameters.pop("cable_length"), spring={**record["spring"], **parameters}
                )
            else:
                record.update(parameters)
                record.update(
                    {
                        end: {"body": point["body"], "point": point["point"]}
                        for end, point in zip(spring.anchors, points)
                    }
                )
            records.append(spring_from_dict(record))
        return records

    def spring_mass(self) -> SpringMass:
        """The springs' total mass [kg] against the floor of the springs that balance the arm and against the
        arm's moving mass (:func:`springbalance.design.spring_mass.spring_mass`, docs/model.md §5.1)."""
        return spring_mass(self.problem, self.x)

    def helical_sizing(self, material: Material | str | None = None) -> dict[str, HelicalDesign]:
        """Helical springs that realise this design (:func:`springbalance.springs.sizing.size_helical_spring`).

        Sizes every spring with a ``helical`` option (with its material), or, when ``material``
        is given, every extension and compression spring (not gas springs) with that material.
        Inputs per spring: its rate ``k``, free length ``l0``, the longest and shortest length
        and the largest force magnitude over the workspace. Returns spring name →
        :class:`~springbalance.springs.sizing.HelicalDesign` (``feasible`` False with the reasons when no
        helical spring can do it).
        """
        designs: dict[str, HelicalDesign] = {}
        for column, spring in enumerate(self.problem.springs):
            option = getattr(spring, "helical", None)
            kind = getattr(spring, "helical_kind", None)
            if kind is None or (option is None and material is None) or hasattr(spring, "spec_sheet"):
                continue  # not a coil, nothing asked, or a coil already (its spec sheet says it all)
            values = self.problem.model.spring_values(spring, self.x)
            lengths, forces = self.evaluation.lengths[:, column], self.evaluation.tensions[:, column]
            if material is not None:
                chosen = material
            else:
                assert option is not None  # skipped above when neither is given
                chosen = option.material
            if values["stiffness"] <= 0:
                continue
            designs[_named(spring)] = size_helical_spring(
                values["stiffness"],
                values["free_length"],
                float(np.max(lengths)),
                float(np.max(np.abs(forces))),
                material=chosen,
                kind=kind,
                min_length=float(np.min(lengths)),
            )
        return designs

    # ---------------------------------------------------------------- torques
    def residual_torque(self, joint_values: npt.ArrayLike | None = None, degrees: bool = False) -> np.ndarray:
        """Actuator torque ``tau(q)`` with the springs (N×nv) [N·m or N].

        ``joint_values``: N×nv joint coordinates (or one row); default: the workspace.
        """
        if joint_values is None:
            return self.evaluation.tau.copy()
        return self.evaluate_on(Workspace.from_array(self.problem.mechanism, joint_values, degrees=degrees)).tau

    def evaluate_on(self, workspace: Workspace) -> Evaluation:
        """Evaluation of this design on another workspace of the same mechanism."""
        problem = DesignProblem(
            self.problem.mechanism,
            workspace,
            self.fixed_springs(),
            objective="rms",
            weights=self.problem.weights_by_name(),
        )
        return problem.evaluate(np.zeros(0))

    def on_workspace(self, workspace: Workspace) -> EvaluatedDesign:
        """This design re-evaluated on ``workspace`` (same objective when the workspace allows it)."""
        objective = self.problem.objective.name
        if OBJECTIVES[objective].needs_path and not workspace.ordered:
            objective = "rms"
        problem = DesignProblem(
            self.problem.mechanism,
            workspace,
            self.fixed_springs(),
            objective=objective,
            weights=self.problem.weights_by_name(),
        )
        return type(self)(problem, np.zeros(0), method="evaluate", status="evaluated")

    def scenario_results(self) -> list[EvaluatedDesign]:
        """Per scenario of the problem, this design fixed in that scenario: on the base workspace, with that
        scenario's masses and its value of every per-scenario variable (empty without scenarios)."""
        problem = self.problem
        designs = []
        for index, scenario in enumerate(problem.scenarios):
            fixed = problem.scenario_problem(index, problem.scenario_springs(self.x, index))
            designs.append(type(self)(fixed, np.zeros(0), status=f"scenario {scenario.name}"))
        return designs

    # ---------------------------------------------------------------- metrics
    def metrics(self) -> dict[str, Any]:
        """Per-joint peak/RMS before and after, reduction %, and every objective before and after."""
        problem = self.problem
        kinematics = problem.workspace.kinematics()
        before_tau, after_tau = kinematics.gravity_torque, self.evaluation.tau
        # a joint that gravity does not load (|g| at round-off level) has no meaningful reduction
        negligible = 1e-9 * max(float(np.max(np.abs(before_tau))), 1e-300)
        joints = [
            {
                **{key: row[key] for key in ("joint", "unit", "peak_before", "peak_after")},
                "peak_reduction_percent": _reduction(row["peak_before"], row["peak_after"], negligible),
                **{key: row[key] for key in ("rms_before", "rms_after")},
                "rms_reduction_percent": _reduction(row["rms_before"], row["rms_after"], negligible),
            }
            for row in torque_rows(problem, after_tau)
        ]
        objectives = {}
        for name, cls in OBJECTIVES.items():
            objective = cls()
            before = objective.value(before_tau * problem.weights, kinematics.potential, problem.path_steps)
            after = objective.value(after_tau * problem.weights, self.evaluation.potential, problem.path_steps)
            objectives[name] = {
                "before": before,
                "after": after,
                "unit": objective.unit,
                "reduction_percent": _reduction(before, after),
            }
        return {
            "joints": joints,
            "objectives": objectives,
            "optimised": problem.objective.name,
            "max_violation": self.evaluation.max_violation,
            "samples": problem.workspace.size,
        }

    def joints_made_worse(self, tolerance: float = TORQUE_TOLERANCE) -> list[dict[str, Any]]:
        """The joints that carry more torque with the springs than without (:mod:`springbalance.design.worse_joints`):
        the rows of :meth:`metrics`, each with ``"worse"``: which of ``"peak"`` and ``"RMS"`` grew. Every joint,
        whatever its weight (the caller decides what a joint of weight 0 means)."""
        return worse_rows(self.metrics()["joints"], tolerance)

    def exact_balance(self, tolerance: float = 1e-9) -> dict[str, Any]:
        """Whether the design balances exactly: residual torque zero to solver precision.

        With scenarios, ``potential_spread`` is the largest spread within one scenario and
        ``scenario_potentials`` the mean potential of each.
        ``relative_residual``: largest ``|tau|`` over the samples and the joints with a weight
        above 0 (the joints the design is asked to balance), divided by the largest unbalanced
        ``|g|`` of those joints [1]; ``exact``: ``relative_residual ≤ tolerance``; ``potential``: the
        mean total potential ``V_g + Σ V_s`` [J] (constant when exact); ``potential_spread``: its
        max − min over the samples [J].
        """
        balanced = self.problem.weights > 0  # joints with weight 0 are not asked to be balanced
        unbalanced = float(np.max(np.abs(self.problem.workspace.kinematics().gravity_torque[:, balanced])))  # [N·m]
        residual = float(np.max(np.abs(self.evaluation.tau[:, balanced])))  # [N·m]
        relative = residual / unbalanced if unbalanced > 0 else float("nan")
        # one block of samples per scenario: each load case has its own constant potential
        potential = self.evaluation.potential.reshape(self.problem.model.n_scenarios, -1)  # [J]
        return {
            "exact": bool(relative <= tolerance),
            "relative_residual": relative,
            "residual": residual,
            "potential": float(np.mean(potential)),
            "potential_spread": float(np.max(np.ptp(potential, axis=1))),
            "scenario_potentials": np.mean(potential, axis=1).tolist(),
        }

    def spread(self) -> dict[str, Any]:
        """Objective values across multi-start starts: best, median, worst, feasible count."""
        values = np.array([record.objective for record in self.starts if record.feasible])
        if values.size == 0:
            return {"starts": len(self.starts), "feasible": 0}
        return {
            "starts": len(self.starts),
            "feasible": int(values.size),
            "best": float(values.min()),
            "median": float(np.median(values)),
            "worst": float(values.max()),
        }

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.problem!r}, status={self.status!r})"


def _reduction(before: float, after: float, negligible: float = 0.0) -> float:
    """Percentage reduction; NaN when there was nothing to reduce (``before ≤ negligible``)."""
    if not np.isfinite(before) or before <= negligible:
        return float("nan")
    return 100.0 * (before - after) / before
