r"""Residual torque as a CasADi function of the design variables only.

Pinocchio stays numeric: for each workspace sample the :class:`~springbalance.model.kinematics.WorkspaceKinematics`
cache supplies ``g(q)``, ``V_g(q)`` and, for every moving body that carries a spring end,
its placement ``(R, t)`` and Jacobian ``J`` (LOCAL_WORLD_ALIGNED); the workspace supplies
the coordinates ``q_i`` of the joints that carry torsional springs. These numbers form the
*sample data* column. For a fixed sample each spring end is affine in its anchor
coordinates (docs/model.md §2):

.. math::
    r = R\,p,\quad x = t + r,\quad J_p^T f = J_{lin}^T f + J_{ang}^T (r \times f),

so the per-sample CasADi function ``sample(x, data) -> (tau, V, L, F, C)`` is small and exact,
and ``sample.map(N)`` evaluates it over the workspace with exact derivatives. Each spring
element (:class:`~springbalance.springs.laws.Spring`) adds its own share through
:meth:`~springbalance.springs.Spring.contribution`, given a :class:`SampleContext`:

.. math:: \tau = g + \sum_s \tau_s,\qquad V = V_g + \sum_s V_s,

with :math:`\tau_s = F_s(L_s)\,(J_{p_b} - J_{p_a})^T u_s` (plus the weight of the spring's
own mass) for a two-point spring and :math:`\tau_s = (k (q_i - q_0) + \tau_0)\, e_i` for a
torsional spring.

Scenarios (:mod:`springbalance.design.scenarios`): the samples of S load cases are stacked, and the data
column ends with S selectors (1 for the sample's scenario, else 0). A per-scenario variable has S
copies in ``x``; the springs see :math:`\sum_s \mathrm{sel}_s\, x_{copy_s}`, i.e. their own
scenario's copy. Without scenarios nothing is added.

Outputs per sample: ``tau`` (nv) [N·m or N], ``V`` (1) [J], spring states ``L`` (n_s: length
[m] or joint angle [rad]), generalised forces ``F`` (n_s: tension [N] or torque [N·m]), and
the constraint rows ``C`` (≥ 0 when feasible): the springs' practical constraints, then, with
``joint_limits`` (``no_joint_worse``), one row :math:`(P_j^2 - \tau_j^2)/P_j` per limited joint.
"""

from __future__ import annotations

import contextlib
import ctypes
import dataclasses
import functools
import os
import queue
import shutil
import threading
from typing import Sequence

import casadi as ca
import numpy as np
import pinocchio as pin

from springbalance.design.block_kernel import SOURCE_ATTRIBUTE, block_kernel
from springbalance.errors import InputError
from springbalance.model.mechanism import Mechanism
from springbalance.springs.params import Free
from springbalance.springs.laws import Spring


@dataclasses.dataclass
class DesignVariables:
    """The design vector ``x`` in physical units: names, bounds and first guess."""

    names: list[str] = dataclasses.field(default_factory=list)
    units: list[str] = dataclasses.field(default_factory=list)
    lower: list[float] = dataclasses.field(default_factory=list)
    upper: list[float] = dataclasses.field(default_factory=list)
    start: list[float] = dataclasses.field(default_factory=list)

    def add(self, name: str, unit: str, lower: float, upper: float, start: float) -> int:
        self.names.append(name)
        self.units.append(unit)
        self.lower.append(float(lower))
        self.upper.append(float(upper))
        self.start.append(float(start))
        return len(self.names) - 1

    @property
    def size(self) -> int:
        return len(self.names)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return np.array(self.lower), np.array(self.upper)


@dataclasses.dataclass(frozen=True)
class ConstraintBlock:
    """Rows of one practical constraint of one spring (or, with ``spring == ""``, of the problem,
    such as ``no_joint_worse.<joint>``): N rows, one per sample, ``≥ 0``."""

    spring: str
    name: str
    unit: str
    offset: int  # first row of this block in the per-sample constraint vector
    scale: float  # typical size of a violation [unit], for the solver's scaling
    #: False when the row does not depend on the sample (a coil's index, its initial tension): the
    #: NLP then keeps it once instead of once per sample
    per_sample: bool = True


class SampleContext:
    """What a spring element sees of one sample (CasADi symbols of the data column).

    ``point(body, p)`` → :class:`PointKinematics` of the body-fixed point ``p``;
    ``coordinate(joint)`` → the joint coordinate ``q_i`` [rad or m];
    ``direction(joint)`` → the unit torque vector ``e_i`` (nv); ``zero()`` → nv zeros;
    ``gravity`` → the gravity vector (3) [m/s²].
    """

    def __init__(self, nv: int, gravity: np.ndarray, bodies: dict, ground: dict, coordinates: dict, joint_index: dict):
        self.nv = nv
        self.gravity = ca.DM(np.asarray(gravity, dtype=float).reshape(3, 1))
        self._bodies, self._ground, self._coordinates, self._joint_index = bodies, ground, coordinates, joint_index

    def point(self, body: str, local) -> "PointKinematics":
        if body in self._bodies:
            t, R, J = self._bodies[body]
            lever = ca.mtimes(R, local)                  # R p, world-aligned [m]
            return PointKinematics(t + lever, lever, J, self.nv)
        t0, R0 = self._ground[body]
        return PointKinematics(ca.DM(t0) + ca.mtimes(ca.DM(R0), local), None, None, self.nv)

    def coordinate(self, joint: str):
        return self._coordinates[joint]

    def direction(self, joint: str) -> ca.DM:
        unit = np.zeros(self.nv)
        unit[self._joint_index[joint]] = 1.0
        return ca.DM(unit)

    def zero(self) -> ca.DM:
        return ca.DM.zeros(self.nv, 1)


class PointKinematics:
    """A body-fixed point at one sample: world ``position`` and the map ``f -> J_p^T f``."""

    def __init__(self, position, lever, jacobian, nv: int):
        self.position, self._lever, self._jacobian, self._nv = position, lever, jacobian, nv

    def generalized(self, force):
        """``J_p^T f`` (nv): the joint torques of a force ``f`` [N] applied at the point (0 on the ground)."""
        if self._jacobian is None:
            return ca.DM.zeros(self._nv, 1)
        J = self._jacobian
        return ca.mtimes(J[:3, :].T, force) + ca.mtimes(J[3:, :].T, ca.cross(self._lever, force))


class TorqueModel:
    """Symbolic residual torque of a mechanism carrying springs.

    Attributes:
        variables: the design variables (names, bounds, first guess) in physical units.
        bodies: moving bodies whose kinematics enter the sample data.
        joints: joints whose coordinates enter the sample data (torsional springs).
        sample: ``Function(x, data) -> (tau, V, L, F, C)`` for one sample.
        constraint_blocks: which spring constraint each row of ``C`` belongs to.
    """

    def __init__(self, mechanism: Mechanism, springs: list[Spring], scenarios: Sequence[str] = (),
                 per_scenario: Sequence[str] = (), joint_limits: np.ndarray | None = None):
        self.mechanism = mechanism
        self.springs = springs
        self.variables = DesignVariables()
        nv = mechanism.nv
        self.bodies = _moving_bodies(mechanism, springs)
        self.joints = _spring_joints(mechanism, springs)
        self._ground = _ground_placements(mechanism, springs)

        # Design variables: every free anchor coordinate and every Free parameter.
        variable_slots = []  # (spring, end, region, index list)
        for spring in springs:
            for end, anchor in spring.anchors.items():
                region = anchor.region()
                indices = [self.variables.add(f"{spring.name}.{end}.{label}", "m" if len(region.labels) != 1 or label != "s" else "1",
                                              lo, hi, s0)
                           for label, lo, hi, s0 in zip(region.labels, region.lower, region.upper, region.start)]
                variable_slots.append((spring, end, region, indices))
            for key, value in spring.parameters.items():
                if isinstance(value, Free) and value.upper > value.lower:
                    self.variables.add(f"{spring.name}.{key}", spring.parameter_units[key],
                                       float(value.lower), float(value.upper), float(value.start))
        self._index = {name: i for i, name in enumerate(self.variables.names)}
        self.base_variables = self.variables
        self.scenarios = list(scenarios)
        self._columns = self._scenario_variables(per_scenario)
        x = ca.SX.sym("x", self.variables.size)

        # Sample data: g (nv), V_g (1), q_i of each spring joint (n_j), then per moving body
        # t (3), R (9, row-major), J (6·nv, row-major); with scenarios, one selector per
        # scenario last (1 in the samples of that scenario, else 0).
        self.data_size = nv + 1 + len(self.joints) + len(self.bodies) * (12 + 6 * nv) + len(self.scenarios)
        data = ca.SX.sym("data", self.data_size)
        local = self._local_symbols(x, data[self.data_size - len(self.scenarios):]) if self.scenarios else x
        gravity_torque, gravity_potential = data[:nv], data[nv]
        coordinates = {joint: data[nv + 1 + slot] for slot, joint in enumerate(self.joints)}
        body_data = {}
        offset = nv + 1 + len(self.joints)
        for body in self.bodies:
            t = data[offset:offset + 3]
            R = ca.reshape(data[offset + 3:offset + 12], 3, 3).T
            J = ca.reshape(data[offset + 12:offset + 12 + 6 * nv], nv, 6).T
            body_data[body] = (t, R, J)
            offset += 12 + 6 * nv
        context = SampleContext(nv, mechanism.gravity, body_data, self._ground, coordinates,
                                {joint: mechanism.joint(joint).index_v for joint in self.joints})

        tau, potential = gravity_torque, gravity_potential
        states, forces, constraint_rows = [], [], []
        self.constraint_blocks: list[ConstraintBlock] = []
        points = {}
        for spring, end, region, indices in variable_slots:
            point = ca.DM(region.offset) + (ca.mtimes(ca.DM(region.basis), local[indices]) if indices else 0)
            points[(spring.name, end)] = point
        for spring in springs:
            parameters = self.parameter_values(spring, local)
            own_points = {end: points[(spring.name, end)] for end in spring.anchors}
            share = spring.contribution(context, parameters, own_points)
            tau = tau + share.torque
            potential = potential + share.potential
            states.append(share.state)
            forces.append(share.force)
            for constraint in spring.constraints():
                parts = getattr(constraint, "parts", None)
                rows = (constraint.rows(share.state, share.force, parameters, share.extra)
                        if getattr(constraint, "uses_extra", False) else constraint.rows(share.state, share.force, parameters))
                if parts is None:
                    parts, rows = ((constraint.name, constraint.unit, constraint.scale),), [rows]
                for (name, unit, scale), row in zip(parts, rows):
                    row = ca.SX(row)
                    self.constraint_blocks.append(ConstraintBlock(spring.name, name, unit, len(constraint_rows),
                                                                  float(scale), bool(ca.depends_on(row, data))))
                    constraint_rows.append(row)

        if joint_limits is not None:
            selectors = data[self.data_size - len(self.scenarios):] if self.scenarios else None
            self._add_joint_limits(np.asarray(joint_limits, dtype=float), tau, selectors, constraint_rows)

        self.n_springs = len(springs)
        self.n_constraints = len(constraint_rows)
        outputs = [tau, potential, ca.vertcat(*states), ca.vertcat(*forces), ca.vertcat(*constraint_rows)]
        self.sample = ca.Function("sample", [x, data], outputs, ["x", "data"], ["tau", "V", "L", "F", "C"])
        self._x = x

    def _add_joint_limits(self, limits: np.ndarray, tau, selectors, constraint_rows: list) -> None:
        r"""Rows :math:`(P_j^2 - \tau_j^2)/P_j \ge 0`, i.e. :math:`|\tau_j| \le P_j`, for every joint
        whose limit ``P_j`` [N·m or N] is finite. ``limits`` is (S×nv) with scenarios (a sample sees
        its own scenario's row through the selectors), else (1×nv); NaN: no row for that joint."""
        limits = limits.reshape(-1, self.mechanism.nv)
        for joint in self.mechanism.joints:
            column = limits[:, joint.index_v]
            if not np.all(np.isfinite(column)):
                continue
            if np.any(column <= 0):
                raise InputError(f"joint limit of {joint.name!r} must be > 0, got {column.min()}")
            if selectors is None or column.size == 1:
                bound = float(column[0])
            else:
                bound = sum(selectors[s] * float(column[s]) for s in range(column.size))
            torque = tau[joint.index_v]
            self.constraint_blocks.append(ConstraintBlock("", f"no_joint_worse.{joint.name}", joint.torque_unit,
                                                          len(constraint_rows), float(np.max(column))))
            constraint_rows.append((bound * bound - torque * torque) / bound)

    # ---------------------------------------------------------------- scenarios
    def _scenario_variables(self, per_scenario) -> np.ndarray:
        """With scenarios: replace every variable named in (or under) ``per_scenario`` by one copy
        per scenario, ``<name>[<scenario>]``. Returns the S×n_base map base index → full index."""
        base = self.base_variables
        per_scenario = list(per_scenario)
        self.per_scenario: list[int] = []  # base indices of the per-scenario variables
        if not self.scenarios:
            if per_scenario:
                raise InputError(f"per-scenario variables {', '.join(per_scenario)} need scenarios")
            return np.arange(base.size)[None, :]
        adjustable = set()
        for entry in per_scenario:
            matches = [i for i, name in enumerate(base.names) if name == entry or name.startswith(entry + ".")]
            if not matches:
                raise InputError(f"per-scenario variable {entry!r} matches no design variable; variables: "
                                 f"{', '.join(base.names) or '(none)'}")
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

    def _local_symbols(self, x, selectors):
        """The base design vector seen by one sample: shared entries of ``x``, and for per-scenario
        variables ``Σ_s selector_s · x[copy_s]`` (the selector is 1 for the sample's scenario)."""
        entries = []
        for i in range(self.base_variables.size):
            column = self._columns[:, i]
            if np.all(column == column[0]):
                entries.append(x[int(column[0])])
            else:
                entries.append(sum(selectors[s] * x[int(column[s])] for s in range(len(self.scenarios))))
        return ca.vertcat(*entries) if entries else ca.SX(0, 1)

    def scenario_vector(self, x, scenario: int = 0) -> np.ndarray:
        """The base design vector (names in :attr:`base_variables`) of scenario ``scenario``."""
        return np.asarray(x, dtype=float)[self._columns[scenario]]

    @property
    def n_scenarios(self) -> int:
        return max(len(self.scenarios), 1)

    # ---------------------------------------------------------------- design vector
    def parameter_values(self, spring: Spring, x):
        """Map of the spring's parameters to numbers or entries of the base vector ``x``."""
        values = {}
        for key, value in spring.parameters.items():
            name = f"{spring.name}.{key}"
            if name in self._index:
                values[key] = x[self._index[name]]
            else:
                values[key] = float(value.lower) if isinstance(value, Free) else float(value)
        return values

    @property
    def linear_indices(self) -> list[int]:
        """Indices of design variables that the torque and the potential depend on linearly
        (stiffness, initial tension, preload, constant force; not the stiffness of a spring whose
        mass is coupled to it): for fixed other variables they solve a linear least-squares problem."""
        base = [self._index[f"{spring.name}.{key}"] for spring in self.springs for key in spring.linear_parameters
                if f"{spring.name}.{key}" in self._index]
        return sorted({int(column) for i in base for column in self._columns[:, i]})

    def anchor_point(self, spring: Spring, end: str, x: np.ndarray, scenario: int = 0) -> np.ndarray:
        """Body-frame anchor point [m] of end ``"a"``/``"b"`` for design vector ``x`` (in ``scenario``)."""
        x = self.scenario_vector(x, scenario)
        region = spring.anchors[end].region()
        coordinates = [x[self._index[f"{spring.name}.{end}.{label}"]] for label in region.labels]
        return region.point(coordinates)

    def spring_values(self, spring: Spring, x: np.ndarray, scenario: int = 0) -> dict:
        """Numeric parameter values of ``spring`` for design vector ``x`` (in ``scenario``)."""
        x = self.scenario_vector(x, scenario)
        return {key: float(value) for key, value in self.parameter_values(spring, x).items()}

    # ---------------------------------------------------------------- numeric data
    def data_matrix(self, kinematics) -> np.ndarray:
        """Sample data columns (data_size × N, Fortran order) from a workspace's numeric cache."""
        kinematics.prepare(self.bodies)
        n = kinematics.gravity_torque.shape[0]
        blocks = [kinematics.gravity_torque, kinematics.potential[:, None]]
        joint_values = kinematics.workspace.joint_values
        for joint in self.joints:
            column = self.mechanism.joint(joint).index_v
            blocks.append(joint_values[:, column:column + 1])
        for body in self.bodies:
            body_kinematics = kinematics.body(body)
            blocks += [body_kinematics.translation, body_kinematics.rotation.reshape(n, 9),
                       body_kinematics.jacobian.reshape(n, -1)]
        if self.scenarios:
            if n % len(self.scenarios):
                raise InputError(f"{n} samples do not split into {len(self.scenarios)} scenario blocks")
            blocks.append(np.kron(np.eye(len(self.scenarios)), np.ones((n // len(self.scenarios), 1))))
        return np.hstack(blocks).T   # Fortran order: each sample's column is contiguous, as the evaluators read it

    @staticmethod
    def known_zeros(data: ca.SX, values: np.ndarray) -> ca.SX:
        """The data symbols ``data`` with the entries that are zero in every column of ``values``
        (the data matrix) replaced by structural zeros, such as a body's Jacobian columns of the
        joints beyond it. An expression built on them drops the terms
        that are exactly zero for these samples (fewer operations, structurally zero derivatives)
        and is valid for these samples only."""
        zero = ~np.any(np.asarray(values) != 0.0, axis=1)
        return ca.vertcat(*[ca.SX(0) if zero[i] else data[i] for i in range(data.numel())])

    @functools.lru_cache(maxsize=8)
    def mapped(self, n: int) -> ca.Function:
        """``sample`` evaluated on ``n`` data columns (serial map: a loop in C)."""
        return self.sample.map(n, "serial")

    def evaluate(self, x, data: np.ndarray) -> dict[str, np.ndarray]:
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


def compiler_available() -> bool:
    """True when a C compiler is on PATH, so CasADi can JIT-compile the per-sample functions."""
    return shutil.which(os.environ.get("CC", "gcc")) is not None or shutil.which("cc") is not None


def compiled(function: ca.Function) -> ca.Function:
    """``function`` compiled to C when a compiler is available (about 8× faster than CasADi's
    virtual machine for these functions), else ``function`` itself.

    The compiled library is cached on disk (:mod:`springbalance.design.compile_cache`): a second
    process on the same problem loads it without running the compiler. Set
    ``SPRINGBALANCE_JIT=0`` to disable compilation.

    The compiled function keeps ``function`` (an attribute): :class:`BlockEvaluator` and
    :class:`SampleEvaluator` build its block kernel from it when they evaluate it over
    :data:`~springbalance.design.block_kernel.KERNEL_MIN_SAMPLES` samples or more (:func:`~springbalance.design.block_kernel.block_kernel_code`).
    """
    if os.environ.get("SPRINGBALANCE_JIT", "1") == "0" or not compiler_available():
        return function
    from springbalance.design.compile_cache import compile_function

    try:
        result = compile_function(function)
    except RuntimeError:  # compiler present but unusable: stay on the virtual machine
        return function
    try:
        setattr(result, SOURCE_ATTRIBUTE, function)
    except AttributeError:
        pass
    return result


#: threads of a block pass (:meth:`BlockEvaluator.blocks`): ``1`` evaluates the blocks in the
#: caller's thread; default 2 when the process may use 2 cores (not in a worker process of a pool)
THREADS_ENV = "SPRINGBALANCE_THREADS"


def count_from_environment(name: str) -> int | None:
    """The integer ≥ 1 that environment variable ``name`` holds, None when it is unset or empty;
    :class:`~springbalance.errors.InputError` naming the variable for anything else."""
    text = os.environ.get(name, "").strip()
    if not text:
        return None
    try:
        value = int(text)
    except ValueError:
        raise InputError(f"{name} must be an integer ≥ 1, got {text!r}") from None
    if value < 1:
        raise InputError(f"{name} must be an integer ≥ 1, got {value}")
    return value


_ONE_THREAD = False   # set in the worker processes of a pool of starts (which already use the cores)


def use_one_thread() -> None:
    """Evaluate block passes in the calling thread only, from now on in this process (the pool's
    worker processes call it: the pool already uses the cores)."""
    global _ONE_THREAD
    _ONE_THREAD = True


@contextlib.contextmanager
def one_thread():
    """Within the block, block passes run in the calling thread only (a study's task, whose
    processes already spread over the cores)."""
    global _ONE_THREAD
    saved, _ONE_THREAD = _ONE_THREAD, True
    try:
        yield
    finally:
        _ONE_THREAD = saved


def evaluation_threads() -> int:
    """Threads of a block pass: ``$SPRINGBALANCE_THREADS`` when set (1 or 2), else 2 when this process
    may run on 2 cores or more and is not a worker process of a pool of starts, else 1."""
    value = count_from_environment(THREADS_ENV)
    if value is not None:
        return min(value, 2)
    if _ONE_THREAD:
        return 1
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    return 2 if cores >= 2 else 1


class _Outputs:
    """Output buffers of up to ``capacity`` samples, as the evaluators hand them out: output ``i``
    of per-sample shape ``(rows, cols)`` is an ``(n, cols, rows)`` array (a view of the raw
    nonzeros when dense, else a dense array the nonzeros are scattered into)."""

    def __init__(self, function: ca.Function, capacity: int):
        self.capacity = capacity
        self.raw, self._shapes, self._sparse = [], [], []
        for i in range(function.n_out()):
            sparsity = function.sparsity_out(i)
            self.raw.append(np.zeros(sparsity.nnz() * capacity))
            self._shapes.append((sparsity.size2(), sparsity.size1()))
            if sparsity.is_dense():
                self._sparse.append(None)
            else:
                triplet_rows, triplet_cols = sparsity.get_triplet()
                self._sparse.append((np.array(triplet_cols, dtype=int), np.array(triplet_rows, dtype=int),
                                     sparsity.nnz()))
        self.addresses = (ctypes.c_void_p * max(len(self.raw), 1))(*[raw.ctypes.data for raw in self.raw])
        self._views: dict[int, list[np.ndarray]] = {}

    def views(self, n: int) -> list[np.ndarray]:
        """The outputs of the first ``n`` samples (sparse ones scattered from the raw nonzeros now)."""
        if n not in self._views:
            self._views[n] = [raw[: n * (sparse[2] if sparse else shape[0] * shape[1])].reshape(n, *shape)
                              if sparse is None else np.zeros((n,) + shape)
                              for raw, shape, sparse in zip(self.raw, self._shapes, self._sparse)]
        outputs = self._views[n]
        for raw, sparse, out in zip(self.raw, self._sparse, outputs):
            if sparse is not None and sparse[2]:
                cols, rows, nnz = sparse
                out[:, cols, rows] = raw[: n * nnz].reshape(n, nnz)
        return outputs


class SampleEvaluator:
    """Fast numeric evaluation of a per-sample function over fixed sample data.

    Wraps ``function(x, data) -> outputs`` mapped over the N data columns with ``x``
    shared, and evaluates into preallocated NumPy arrays. An output of per-sample shape
    ``(rows, cols)`` comes back as an array ``(N, cols, rows)`` — the per-sample *transpose*,
    which is CasADi's column-major memory read row-major (a view, no copy, for dense outputs).

    When ``function`` comes from :func:`compiled` and there are :data:`~springbalance.design.block_kernel.KERNEL_MIN_SAMPLES` samples
    or more, its block kernel (:func:`~springbalance.design.block_kernel.block_kernel`; ``kernel=False``: never, ``True``: whatever the
    number of samples) evaluates them, 4 at once, bit for bit CasADi's numbers, reading ``x``
    once. Otherwise the map is CasADi's plain
    serial ``Map`` through its zero-copy buffer interface, which reads each sample's inputs in
    place; ``x`` is then repeated once per sample here (N·n_x numbers). A map with ``x`` as a
    shared ("reduced") input would wrap it in an MX function whose work vector copies the data,
    the repeated ``x`` and the outputs on every call: about twice the memory, and slower.
    """

    def __init__(self, function: ca.Function, data: np.ndarray, kernel: bool | None = None):
        n = data.shape[1]
        self.n_samples = n
        self.function = function
        self._kernel = None if kernel is False else block_kernel(function, n if kernel is None else None)
        self._data = np.asfortranarray(data).reshape(-1, order="F")  # a view of Fortran-ordered data, no copy
        self._buffers = _Outputs(function, n)
        if self._kernel is not None:
            return
        self._x = np.zeros((n, function.nnz_in(0)))   # row i: the x of sample i (all equal)
        self._buffer, self._trigger = function.map(n, "serial").buffer()
        self._buffer.set_arg(0, memoryview(self._x.reshape(-1)))
        self._buffer.set_arg(1, memoryview(self._data))
        for i, raw in enumerate(self._buffers.raw):
            self._buffer.set_res(i, memoryview(raw))

    def rebind(self, data: np.ndarray) -> None:
        """Evaluate on other data columns from now on: ``data`` holds ``n_samples`` columns, flat in
        Fortran order (a view, kept alive here)."""
        if data.size != self._data.size:
            raise ValueError(f"{data.size} data values, the evaluator reads {self._data.size}")
        self._data = data
        if self._kernel is None:
            self._buffer.set_arg(1, memoryview(self._data))

    def __call__(self, x) -> list[np.ndarray]:
        if self._kernel is not None:
            data = np.ascontiguousarray(self._data)
            self._kernel(self._kernel.shared_input(x), data.ctypes.data, self.n_samples, self._buffers.addresses)
        else:
            self._x[:] = x
            self._trigger()
        return self._buffers.views(self.n_samples)


#: a block of samples of :class:`BlockEvaluator` holds at most about this many bytes of outputs (two
#: such buffers stay in a 2-core machine's last-level cache; fewer, larger blocks cost less Python per pass)
BLOCK_BYTES = 2 * 1024 * 1024


class BlockEvaluator:
    """A per-sample function evaluated over the samples block by block, into buffers of one block.

    ``blocks(x)`` yields ``(start, stop, outputs)`` for consecutive blocks of samples; ``outputs``
    are as :class:`SampleEvaluator`'s for the block's samples and are overwritten by the next block.
    The sample data is read in place (no copy when it is in Fortran order, as
    :meth:`TorqueModel.data_matrix` makes it), and the outputs never exist for all samples at
    once: a caller that reduces each block (``JᵀJ``, ``Jᵀr``) needs memory for one block only.

    With a block kernel (as :class:`SampleEvaluator`) and 2 threads (:func:`evaluation_threads`),
    a helper thread evaluates block k+1 while the caller reduces block k (the kernel runs without
    the GIL, NumPy's BLAS too): the two buffers alternate, and each block's outputs are the same
    numbers, handed out in the same order, as with one thread.

    Args:
        block: samples per block; default: blocks of equal size (to a sample) whose outputs take at
            most about :data:`BLOCK_BYTES`.
        kernel: use the block kernel: None (default) from :data:`~springbalance.design.block_kernel.KERNEL_MIN_SAMPLES` samples on,
            False never (CasADi's map), True whenever ``function`` has one.
    """

    def __init__(self, function: ca.Function, data: np.ndarray, block: int | None = None,
                 kernel: bool | None = None):
        self.function = function
        self.n_samples = n = data.shape[1]
        self._rows = data.shape[0]
        self._data = np.asfortranarray(data).reshape(-1, order="F")
        if block is None:
            per_sample = 8 * max(sum(function.sparsity_out(i).nnz() for i in range(function.n_out())), 1)
            largest = max(BLOCK_BYTES // per_sample, 32)
            block = -(-n // -(-n // largest))   # ceil(n / ceil(n / largest)): the blocks share the samples evenly
        self.block = int(max(1, min(block, n)))
        self._parts: dict[int, SampleEvaluator] = {}
        self._kernel = None if kernel is False else block_kernel(function, n if kernel is None else None)
        self._buffers: list[_Outputs] = []

    def _part(self, size: int) -> SampleEvaluator:
        if size not in self._parts:
            self._parts[size] = SampleEvaluator(self.function, self._data[: size * self._rows].reshape(
                self._rows, size, order="F"), kernel=False)
        return self._parts[size]

    def _slot(self, index: int) -> _Outputs:
        while len(self._buffers) <= index:
            self._buffers.append(_Outputs(self.function, self.block))
        return self._buffers[index]

    def blocks(self, x):
        """``(start, stop, outputs)`` of each block of samples, in order."""
        spans = [(start, min(start + self.block, self.n_samples)) for start in range(0, self.n_samples, self.block)]
        if self._kernel is None:
            for start, stop in spans:
                part = self._part(stop - start)
                part.rebind(self._data[start * self._rows: stop * self._rows])
                yield start, stop, part(x)
            return
        x = self._kernel.shared_input(x)   # a copy: the helper thread reads it while the caller goes on
        if len(spans) < 2 or evaluation_threads() < 2:
            slot = self._slot(0)
            for start, stop in spans:
                self._evaluate(x, start, stop, slot)
                yield start, stop, slot.views(stop - start)
            return
        yield from self._pipelined(x, spans)

    def _evaluate(self, x: np.ndarray, start: int, stop: int, slot: _Outputs) -> None:
        self._kernel(x, self._data.ctypes.data + 8 * start * self._rows, stop - start, slot.addresses)

    def _pipelined(self, x: np.ndarray, spans):
        """The blocks with a helper thread one block ahead (two buffers; each reply is the helper's
        error or None)."""
        slots = (self._slot(0), self._slot(1))
        requests, replies = queue.SimpleQueue(), queue.SimpleQueue()

        def helper():
            while True:
                index = requests.get()
                if index is None:
                    return
                try:
                    self._evaluate(x, *spans[index], slots[index % 2])
                    replies.put(None)
                except BaseException as error:   # handed to the caller's thread
                    replies.put(error)

        thread = threading.Thread(target=helper, name="springbalance-blocks", daemon=True)
        thread.start()
        try:
            requests.put(1)
            self._evaluate(x, *spans[0], slots[0])
            for index, (start, stop) in enumerate(spans):
                if index:
                    error = replies.get()
                    if error is not None:
                        raise error
                    if index + 1 < len(spans):   # the caller is done with the other buffer (block index - 1)
                        requests.put(index + 1)
                yield start, stop, slots[index % 2].views(stop - start)
        finally:
            requests.put(None)
            thread.join()

    def evaluate(self, x) -> list[np.ndarray]:
        """Every output for all samples, ``(N, cols, rows)`` arrays as :class:`SampleEvaluator`'s (new arrays)."""
        full = None
        for start, stop, outputs in self.blocks(x):
            if full is None:
                full = [np.empty((self.n_samples,) + out.shape[1:]) for out in outputs]
            for whole, out in zip(full, outputs):
                whole[start:stop] = out
        return full
