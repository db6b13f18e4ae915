"""The per-sample symbolic model (:class:`TorqueModel`): ``sample(x, data) -> (tau, V, L, F, C)`` of a
mechanism carrying springs (see :mod:`springbalance.design.torque_model`)."""

from __future__ import annotations

import functools
from typing import Any, Sequence, cast

import casadi as ca
import numpy as np
import numpy.typing as npt
import pinocchio as pin

from springbalance.design.torque_model.context import SampleContext
from springbalance.design.torque_model.variables import ConstraintBlock, DesignVariables
from springbalance.errors import InputError
from springbalance.model.kinematics import StackedKinematics, WorkspaceKinematics
from springbalance.model.mechanism import Mechanism
from springbalance.model.workspace import Workspace
from springbalance.springs.laws import Contribution, Spring
from springbalance.springs.params import Free


class TorqueModel:
    """Symbolic residual torque of a mechanism carrying springs.

    Attributes:
        variables: the design variables (names, bounds, first guess) in physical units.
        bodies: moving bodies whose kinematics enter the sample data.
        joints: joints whose coordinates enter the sample data (torsional springs).
        sample: ``Function(x, data) -> (tau, V, L, F, C)`` for one sample.
        constraint_blocks: which spring constraint each row of ``C`` belongs to.
    """

    def __init__(
        self,
        mechanism: Mechanism,
        springs: list[Spring],
        scenarios: Sequence[str] = (),
        per_scenario: Sequence[str] = (),
        joint_limits: np.ndarray | None = None,
        max_spring_mass: float | None = None,
        corners: Any = None,
    ) -> None:
        self.mechanism = mechanism
        self.springs = springs
        self.variables = DesignVariables()
        nv = mechanism.nv
        self.bodies = _moving_bodies(mechanism, springs)
        self.joints = _spring_joints(mechanism, springs)
        self._ground = _ground_placements(mechanism, springs)

        variable_slots = self._declare_variables()
        self._index = {name: i for i, name in enumerate(self.variables.names)}
        #: (id of a spring, end) → (the spring, its end's region, the region's columns in x): see anchor_point
        self._anchor_regions: dict[tuple[int, str], tuple[Spring, Any, np.ndarray]] = {}
        self.base_variables = self.variables
        self.scenarios = list(scenarios)
        self._columns = self._scenario_variables(per_scenario)
        #: the tolerance box's corner cases (a :class:`~springbalance.design.tolerance_corners.LawCorners`; their
        #: names are the scenarios) or None: they add each case's law change and its adjuster variables
        self.corners = corners
        if corners is not None:
            corners.declare(self.variables)
        x = ca.SX.sym("x", self.variables.size)
        self._x = x

        # Sample data: g (nv), V_g (1), q_i of each spring joint (n_j), then per moving body
        # t (3), R (9, row-major), J (6·nv, row-major); with scenarios, one selector per
        # scenario last (1 in the samples of that scenario, else 0).
        self.data_size = nv + 1 + len(self.joints) + len(self.bodies) * (12 + 6 * nv) + len(self.scenarios)
        data = ca.SX.sym("data", self.data_size)
        local = self._local_symbols(x, data[self.data_size - len(self.scenarios) :]) if self.scenarios else x
        context = self._sample_context(data)
        tau, potential, states, forces, constraint_rows = self._spring_outputs(context, data, local, variable_slots)

        if joint_limits is not None:
            selectors = data[self.data_size - len(self.scenarios) :] if self.scenarios else None
            gravity = data[:nv]  # the bare arm's generalized gravity g at the sample
            self._add_joint_limits(np.asarray(joint_limits, dtype=float), tau, gravity, selectors, constraint_rows)
        if max_spring_mass is not None:
            self._add_mass_limit(float(max_spring_mass), local, data, constraint_rows)

        self.n_springs = len(springs)
        self.n_constraints = len(constraint_rows)
        outputs = [tau, potential, ca.vertcat(*states), ca.vertcat(*forces), ca.vertcat(*constraint_rows)]
        self.sample = ca.Function("sample", [x, data], outputs, ["x", "data"], ["tau", "V", "L", "F", "C"])

    def _declare_variables(self) -> list[tuple]:
        """Add the design variables: every free anchor coordinate [m] (or arc parameter [1]) and every
        :class:`~springbalance.springs.params.Free` parameter. Returns the anchors' slots
        ``(spring, end, region, indices of its coordinates)``."""
        variable_slots = []  # (spring, end, region, index list)
        #: the names of the constraints' own variables (a coil's fatigue bounds), in the base vector
        self.auxiliary_names: list[str] = []
        for spring in self.springs:
            for end, anchor in spring.anchors.items():
                region = anchor.region()
                indices = [
                    self.variables.add(
                        f"{spring.name}.{end}.{label}",
                        "m" if len(region.labels) != 1 or label != "s" else "1",
                        lo,
                        hi,
                        s0,
                    )
                    for label, lo, hi, s0 in zip(region.labels, region.lower, region.upper, region.start)
                ]
                variable_slots.append((spring, end, region, indices))
            for key, value in spring.parameters.items():
                if isinstance(value, Free) and value.upper > value.lower:
                    self.variables.add(
                        f"{spring.name}.{key}",
                        spring.parameter_units[key],
                        float(value.lower),
                        float(value.upper),
                        float(value.start),
                    )
            for constraint in spring.constraints():  # a constraint's own variables (a coil's fatigue floor)
                for key, unit, lower, upper, start in getattr(constraint, "auxiliary", ()):
                    self.variables.add(f"{spring.name}.{key}", unit, lower, upper, start)
                    self.auxiliary_names.append(f"{spring.name}.{key}")
        return variable_slots

    def _sample_context(self, data: ca.SX) -> SampleContext:
        """What the springs see of the sample data column ``data``: the spring joints' coordinates and
        each moving body's ``(t, R, J)``."""
        mechanism, nv = self.mechanism, self.mechanism.nv
        coordinates = {joint: data[nv + 1 + slot] for slot, joint in enumerate(self.joints)}
        body_data = {}
        offset = nv + 1 + len(self.joints)
        for body in self.bodies:
            t = data[offset : offset + 3]
            R = ca.reshape(data[offset + 3 : offset + 12], 3, 3).T
            J = ca.reshape(data[offset + 12 : offset + 12 + 6 * nv], nv, 6).T
            body_data[body] = (t, R, J)
            offset += 12 + 6 * nv
        return SampleContext(
            nv,
            mechanism.gravity,
            body_data,
            self._ground,
            coordinates,
            {joint: mechanism.joint(joint).index_v for joint in self.joints},
        )

    def _spring_outputs(self, context: SampleContext, data: ca.SX, local: ca.SX, variable_slots: list[tuple]) -> tuple:
        r"""``(tau, V, states, forces, constraint rows)`` of one sample: :math:`\tau = g + \sum_s \tau_s`
        [N·m or N], :math:`V = V_g + \sum_s V_s` [J], each spring's state and force, and the rows of its
        practical constraints (their :class:`ConstraintBlock` recorded in :attr:`constraint_blocks`)."""
        nv = self.mechanism.nv
        tau, potential = data[:nv], data[nv]
        states: list[object] = []
        forces: list[object] = []
        constraint_rows: list[ca.SX] = []
        self.constraint_blocks: list[ConstraintBlock] = []
        points: dict[tuple[str | None, str], ca.DM | ca.SX] = {}
        for spring, end, region, indices in variable_slots:
            point = ca.DM(region.offset) + (ca.mtimes(ca.DM(region.basis), local[indices]) if indices else 0)
            points[(spring.name, end)] = point
        for spring in self.springs:
            parameters = {**self.parameter_values(spring, local), **self.auxiliary_values(spring, local)}
            own_points = {end: points[(spring.name, end)] for end in spring.anchors}
            share = spring.contribution(context, parameters, own_points)
            # Contribution declares its fields as object (springs package); they are CasADi expressions
            tau = tau + cast(ca.SX, share.torque)
            potential = potential + cast(ca.SX, share.potential)
            if self.corners is not None:  # the law of the sample's corner case (the rules keep the nominal one)
                selectors = data[self.data_size - len(self.scenarios) :]
                change = self.corners.deviation(spring, context, parameters, own_points, selectors, self._x)
                if change is not None:
                    tau, potential = tau + change[0], potential + change[1]
            states.append(share.state)
            forces.append(share.force)
            self._add_constraint_rows(spring, share, parameters, data, constraint_rows)
        return tau, potential, states, forces, constraint_rows

    def _add_constraint_rows(
        self, spring: Spring, share: Contribution, parameters: dict, data: ca.SX, constraint_rows: list[ca.SX]
    ) -> None:
        """Append the rows (≥ 0 when feasible) of ``spring``'s practical constraints to ``constraint_rows``."""
        for constraint in spring.constraints():
            parts = getattr(constraint, "parts", None)
            rows = (
                constraint.rows(share.state, share.force, parameters, share.extra)
                if getattr(constraint, "uses_extra", False)
                else constraint.rows(share.state, share.force, parameters)
            )
            if parts is None:
                parts, rows = ((constraint.name, constraint.unit, constraint.scale),), [rows]
            reserves = getattr(constraint, "reserves", {})  # part name → reserve [unit] the rows keep
            once = getattr(constraint, "once", ())  # parts of no sample the solver evaluates once
            extreme = getattr(constraint, "extreme", ())  # parts that bind at their extreme samples only
            for (name, unit, scale), row in zip(parts, rows):
                row = ca.SX(row)
                per_sample = bool(ca.depends_on(row, data))
                self.constraint_blocks.append(
                    ConstraintBlock(
                        spring.name,
                        name,
                        unit,
                        len(constraint_rows),
                        float(scale),
                        per_sample,
                        float(reserves.get(name, 0.0)),
                        not per_sample and name in once,
                        per_sample and name in extreme,
                    )
                )
                constraint_rows.append(row)

    def _add_joint_limits(
        self,
        limits: np.ndarray,
        tau: ca.SX,
        gravity: ca.SX,
        selectors: ca.SX | None,
        constraint_rows: list[ca.SX],
    ) -> None:
        r"""Rows :math:`(L_j^2 - \tau_j^2)/L_j \ge 0`, i.e. :math:`|\tau_j| \le L_j`, for every joint
        whose limit ``P_j`` [N·m or N] is finite, with :math:`L_j = \max(P_j, |g_j|)`: no worse than the bare
        arm's peak over the samples nor than the bare arm at this pose. At the samples :math:`L_j = P_j` (the
        peak is over them); at a pose where the bare arm itself carries more, the springs may leave it that
        (a joint no spring acts on, :math:`\tau_j = g_j`, meets its row everywhere). ``limits`` is (S×nv)
        with scenarios (a sample sees its own scenario's row through the selectors), else (1×nv); NaN: no
        row for that joint."""
        limits = limits.reshape(-1, self.mechanism.nv)
        for joint in self.mechanism.joints:
            column = limits[:, joint.index_v]
            if not np.all(np.isfinite(column)):
                continue
            if np.any(column <= 0):
                raise InputError(f"joint limit of {joint.name!r} must be > 0, got {column.min()}")
            bound: float | ca.SX
            if selectors is None or column.size == 1:
                bound = float(column[0])
            else:  # (sum() of SX is SX: typeshed's sum wants int-addable items)
                bound = cast(ca.SX, sum(selectors[s] * float(column[s]) for s in range(column.size)))
            torque = tau[joint.index_v]
            bound = ca.fmax(bound, ca.fabs(gravity[joint.index_v]))  # data only: the same row's x-derivatives
            self.constraint_blocks.append(
                ConstraintBlock(
                    "", f"no_joint_worse.{joint.name}", joint.torque_unit, len(constraint_rows), float(np.max(column))
                )
            )
            constraint_rows.append((bound * bound - torque * torque) / bound)

    def _add_mass_limit(self, bound: float, local: ca.SX, data: ca.SX, constraint_rows: list[ca.SX]) -> None:
        r"""The row :math:`M - \sum_s m_s(x) \ge 0` [kg] (``max_spring_mass``, docs/model.md §5.1): the parts'
        masses (:meth:`~springbalance.springs.laws.Spring.part_mass`) within the bound ``M`` [kg]. It depends on
        no sample (unless a per-scenario variable changes a mass), so the NLP keeps it once."""
        total = ca.SX(0)
        for spring in self.springs:
            total = total + cast(ca.SX, spring.part_mass(self.parameter_values(spring, local)))
        row = bound - total
        self.constraint_blocks.append(
            ConstraintBlock("", "max_spring_mass", "kg", len(constraint_rows), 0.1 * bound, ca.depends_on(row, data))
        )
        constraint_rows.append(row)

    # ---------------------------------------------------------------- scenarios
    def _scenario_variables(self, per_scenario: Sequence[str]) -> np.ndarray:
        """With scenarios: replace every variable named in (or under) ``per_scenario`` by one copy
        per scenario, ``<name>[<scenario>]``. Returns the S×n_base map base index → full index."""
        base = self.base_variables
        per_scenario = list(per_scenario)
        self.per_scenario: list[int] = []  # base indices of the per-scenario variables
        if not self.scenarios:
            if per_scenario:
                raise InputError(f"per-scenario variables {', '.join(per_scenario)} need scenarios")
            return np.arange(base.size)[None, :]
        adjustable: set[int] = set()
        for entry in per_scenario:
            matches = [i for i, name in enumerate(base.names) if name == entry or name.startswith(entry + ".")]
            if not matches:
                raise InputError(
                    f"per-scenario variable {entry!r} matches no design variable; variables: "
                    f"{', '.join(base.names) or '(none)'}"
                )
            adjustable.update(matches)
        self.per_scenario = sorted(adjustable)
        full = DesignVariables()
        columns = np.zeros((len(self.scenarios), base.size), dtype=int)
        for i, name in enumerate(base.names):
            bounds = (base.units[i], base.lower[i], base.upper[i], base.start[i])
            if i in adjustable:
                for s, scenario in enumerate(self.scenarios):
                    columns[s, i] = full.add(f"{name}[{scenario}]", *bounds)
            else:
                columns[:, i] = full.add(name, *bounds)
        self.variables = full
        return columns

    def _local_symbols(self, x: ca.SX, selectors: ca.SX | None) -> ca.SX:
        """The base design vector seen by one sample: shared entries of ``x``, and for per-scenario
        variables ``Σ_s selector_s · x[copy_s]`` (the selector is 1 for the sample's scenario)."""
        entries: list[ca.SX] = []
        for i in range(self.base_variables.size):
            column = self._columns[:, i]
            if np.all(column == column[0]):
                entries.append(x[int(column[0])])
            else:
                assert selectors is not None  # a variable with per-scenario copies means scenarios
                entries.append(cast(ca.SX, sum(selectors[s] * x[int(column[s])] for s in range(len(self.scenarios)))))
        return ca.vertcat(*entries) if entries else ca.SX(0, 1)

    def scenario_vector(self, x: npt.ArrayLike, scenario: int = 0) -> np.ndarray:
        """The base design vector (names in :attr:`base_variables`) of scenario ``scenario``."""
        return np.asarray(x, dtype=float)[self._columns[scenario]]

    @property
    def n_scenarios(self) -> int:
        return max(len(self.scenarios), 1)

    # ---------------------------------------------------------------- design vector
    def parameter_values(self, spring: Spring, x: ca.SX | np.ndarray) -> dict:
        """Map of the spring's parameters to numbers or entries of the base vector ``x``."""
        values = {}
        for key, value in spring.parameters.items():
            name = f"{spring.name}.{key}"
            if name in self._index:
                values[key] = x[self._index[name]]
            else:
                values[key] = float(value.lower) if isinstance(value, Free) else float(value)
        return values

    def auxiliary_values(self, spring: Spring, x: ca.SX | np.ndarray) -> dict:
        """The entries of the base vector ``x`` of the auxiliary variables of ``spring``'s constraints, by key."""
        prefix = f"{spring.name}."
        keys = [key for constraint in spring.constraints() for key, *_ in getattr(constraint, "auxiliary", ())]
        return {key: x[self._index[prefix + key]] for key in keys if prefix + key in self._index}

    @property
    def linear_indices(self) -> list[int]:
        """Indices of design variables that the torque and the potential depend on linearly
        (stiffness, initial tension, preload, constant force; not the stiffness of a spring whose
        mass is coupled to it): for fixed other variables they solve a linear least-squares problem."""
        base = [
            self._index[f"{spring.name}.{key}"]
            for spring in self.springs
            for key in spring.linear_parameters
            if f"{spring.name}.{key}" in self._index
        ]
        return sorted({int(column) for i in base for column in self._columns[:, i]})

    def anchor_point(self, spring: Spring, end: str, x: npt.ArrayLike, scenario: int = 0) -> np.ndarray:
        """Body-frame anchor point [m] of end ``"a"``/``"b"`` for design vector ``x`` (in ``scenario``)."""
        x = self.scenario_vector(x, scenario)
        cached = self._anchor_regions.get((id(spring), end))
        if cached is None or cached[0] is not spring:  # the region once per spring and end (a clearance check
            region = spring.anchors[end].region()  # asks for each end at thousands of poses)
            columns = np.array([self._index[f"{spring.name}.{end}.{label}"] for label in region.labels], dtype=int)
            cached = self._anchor_regions[(id(spring), end)] = (spring, region, columns)
        return cached[1].point(np.asarray(x)[cached[2]])

    def spring_values(self, spring: Spring, x: np.ndarray, scenario: int = 0) -> dict:
        """Numeric parameter values of ``spring`` for design vector ``x`` (in ``scenario``)."""
        x = self.scenario_vector(x, scenario)
        return {key: float(value) for key, value in self.parameter_values(spring, x).items()}

    # ---------------------------------------------------------------- numeric data
    def data_matrix(self, kinematics: WorkspaceKinematics | StackedKinematics) -> np.ndarray:
        """Sample data columns (data_size × N, Fortran order) from a workspace's numeric cache."""
        kinematics.prepare(self.bodies)
        n = kinematics.gravity_torque.shape[0]
        blocks = [kinematics.gravity_torque, kinematics.potential[:, None]]
        assert isinstance(kinematics.workspace, Workspace)  # the kinematics of a problem's workspace
        joint_values = kinematics.workspace.joint_values
        for joint in self.joints:
            column = self.mechanism.joint(joint).index_v
            blocks.append(joint_values[:, column : column + 1])
        for body in self.bodies:
            body_kinematics = kinematics.body(body)
            blocks += [
                body_kinematics.translation,
                body_kinematics.rotation.reshape(n, 9),
                body_kinematics.jacobian.reshape(n, -1),
            ]
        if self.scenarios:
            if n % len(self.scenarios):
                raise InputError(f"{n} samples do not split into {len(self.scenarios)} scenario blocks")
            blocks.append(np.kron(np.eye(len(self.scenarios)), np.ones((n // len(self.scenarios), 1))))
        return np.hstack(blocks).T  # Fortran order: each sample's column is contiguous, as the evaluators read it

    @staticmethod
    def known_zeros(data: ca.SX, values: np.ndarray) -> ca.SX:
        """The data symbols ``data`` with the entries that are zero in every column of ``values``
        (the data matrix) replaced by structural zeros, such as a body's Jacobian columns of the
        joints beyond it. An expression built on them drops the terms
        that are exactly zero for these samples (fewer operations, structurally zero derivatives)
        and is valid for these samples only."""
        zero = ~np.any(np.asarray(values) != 0.0, axis=1)
        return ca.vertcat(*[ca.SX(0) if zero[i] else data[i] for i in range(data.numel())])

    @functools.lru_cache(maxsize=8)  # noqa: B019  (a model lives as long as its problem; 8 maps at most)
    def mapped(self, n: int) -> ca.Function:
        """``sample`` evaluated on ``n`` data columns (serial map: a loop in C)."""
        return self.sample.map(n, "serial")

    def evaluate(self, x: np.ndarray, data: np.ndarray) -> dict[str, np.ndarray]:
        """Numeric outputs over the samples: tau (N×nv), V (N), L (N×n_s), F (N×n_s), C (N×n_c)."""
        n = data.shape[1]
        tau, potential, lengths, tensions, rows = self.mapped(n)(np.asarray(x, dtype=float), data)
        return {
            "tau": np.array(tau).T.reshape(n, -1),
            "V": np.array(potential).reshape(-1),
            "L": np.array(lengths).T.reshape(n, self.n_springs),
            "F": np.array(tensions).T.reshape(n, self.n_springs),
            "C": np.array(rows).T.reshape(n, self.n_constraints),
        }


def _moving_bodies(mechanism: Mechanism, springs: list[Spring]) -> list[str]:
    bodies = []
    for spring in springs:
        for body in spring.bodies:
            try:
                ground = mechanism.is_ground(body)
            except InputError as error:
                raise InputError(f"spring {spring.name!r}: {error}") from None
            if not ground and body not in bodies:
                bodies.append(body)
    return bodies


def _spring_joints(mechanism: Mechanism, springs: list[Spring]) -> list[str]:
    joints = []
    for spring in springs:
        spring.check(mechanism)
        for joint in spring.joints:
            if joint not in joints:
                joints.append(joint)
    return joints


def _ground_placements(mechanism: Mechanism, springs: list[Spring]) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    model = mechanism.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    placements = {}
    for spring in springs:
        for body in spring.bodies:
            if mechanism.is_ground(body):
                placement = data.oMf[mechanism.frame_id(body)]
                placements[body] = (np.array(placement.translation), np.array(placement.rotation))
    return placements
