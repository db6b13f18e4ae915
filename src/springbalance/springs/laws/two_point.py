r"""Two-point springs: the base class of every law between a point of one body and a point of another.

Every spring is an *element* that adds its share to the holding torque and the potential at
each workspace sample (:meth:`Spring.contribution`):

- **two-point springs** (:class:`TwoPointSpring`) join a point of body A to a point of body
  B (:class:`~springbalance.springs.params.Anchor`). With ``L`` the distance between the ends, the
  spring stores ``V_s(L)`` [J] and pulls the ends together with tension ``F(L) = dV_s/dL``
  [N] (negative for a spring that pushes). Its share of the actuator torque is

  .. math:: \tau_s(q) = F(L)\,(J_{p_b} - J_{p_a})^T u,\qquad u = (x_b - x_a)/L .

  A two-point spring may carry its own mass ``m_s`` (docs/model.md §5), fixed or coupled to its
  rate through the coil geometry (:class:`~springbalance.springs.mass.CoilMass`), as a uniform
  body between its ends: half at each end, which adds :math:`-(m_s/2)(J_{p_a} + J_{p_b})^T g`
  to the torque and :math:`-(m_s/2)\,g \cdot (x_a + x_b)` to the potential (``g`` the gravity vector).
- **joint springs** (such as :class:`~springbalance.springs.laws.torsional.TorsionalSpring`) act
  on one joint coordinate.

A law is one module of this folder with one class: it sets ``kind`` (its ``type`` in configs and
saved designs), its parameters and options, and its force and potential, and it registers itself
in :data:`SPRING_TYPES` by subclassing. Besides the physics, a two-point law says how MuJoCo
expresses it (:meth:`TwoPointSpring.tendon_law`) and where a real part departs from its
idealised law (:meth:`TwoPointSpring.law_warnings`); the scene draws every two-point law as a
helix coloured by its tension, so a law needs nothing there.

Laws are written with plain arithmetic, so one implementation serves CasADi symbols
(inside the optimiser) and NumPy arrays (checks, reports). ``parameters`` maps each
parameter name to its value. Every parameter is a number or :class:`~springbalance.springs.params.Free`.
Each element reports one *state* and one *generalised force* per sample: length [m] and
tension [N] for two-point springs, joint angle [rad] and torque [N·m] for torsional ones.
"""

from __future__ import annotations

import abc
from typing import TYPE_CHECKING, Any, ClassVar, Sequence

import numpy as np

from springbalance.errors import InputError
from springbalance.springs import constraints as practical
from springbalance.springs.helical_option import Helical, helical_from_dict
from springbalance.springs.laws.spring import Contribution, PositiveNumber, Sample, Spring, _positive_option
from springbalance.springs.mass import CoilMass, FixedMass, MassOption, mass_from_record
from springbalance.springs.params import Anchor, Pulley
from springbalance.springs.routing import path_length
from springbalance.springs.values import Parameters, Value, ValueT

if TYPE_CHECKING:
    from springbalance.model.mechanism import Mechanism


class TwoPointSpring(Spring):
    """Base class of springs between two anchors (law ``F(L)``, ``V_s(L)``), with optional mass.

    Options: ``max_force`` [N] (``|F| ≤``), ``max_length`` / ``min_length`` [m], ``mass``:
    a number [kg] or a :class:`CoilMass` (or its record), ``part_number``: the catalogue part
    this spring is (a stock spring; reports show it).

    **Routed** (``via``, ``cable_length``; docs/model.md §3.9): the spring's body lies from ``a``
    towards the first pulley, and a cable of length ``cable_length`` [m] (a parameter, fixed or
    free) runs from the spring's other end over the pulleys ``via``
    (:class:`~springbalance.springs.params.Pulley`) to ``b``. The law's length is then
    ``L = ℓ(path) − cable_length`` (:func:`~springbalance.springs.routing.path_length`), the tension
    acts along every segment, and the spring must fit on its segment: ``L ≤ |P_1 − P_0|`` at every
    sample (the constraint ``fits_segment``). Its own mass hangs at ``a`` and the first pulley.
    """

    ends = ("a", "b")
    option_types = {
        "max_force": PositiveNumber | None,
        "max_length": PositiveNumber | None,
        "min_length": PositiveNumber | None,
        "mass": MassOption | None,
        "part_number": str | None,
    }

    def __init__(
        self,
        a: Anchor,
        b: Anchor,
        name: str | None = None,
        *,
        max_force: float | None = None,
        max_length: float | None = None,
        min_length: float | None = None,
        mass: float | dict | CoilMass | FixedMass | None = None,
        part_number: str | None = None,
        via: Sequence[Pulley] = (),
        **parameters: Any,
    ):
        if not isinstance(a, Anchor) or not isinstance(b, Anchor):
            raise InputError(f"spring {name or ''!s}: ends must be Anchor objects, got {a!r} and {b!r}")
        self.a, self.b = a, b
        via = [via] if isinstance(via, Pulley) else list(via or ())
        if any(not isinstance(pulley, Pulley) for pulley in via):
            raise InputError(f"spring {name or ''!s}: via must be a list of Pulley objects, got {via!r}")
        #: the pulleys (and guide points) of a routed spring, in path order
        self.via = tuple(via)
        if self.via and "cable_length" not in parameters:
            raise InputError(
                f"spring {name or ''!s}: a spring routed over pulleys needs a cable_length (a number or Free, [m])"
            )
        if "cable_length" in parameters:
            # an instance's own parameter list: the law's, and the cable
            self.parameter_units = {**type(self).parameter_units, "cable_length": "m"}
            self.nonnegative = (*type(self).nonnegative, "cable_length")
        super().__init__(name, **parameters)
        self.max_force = _positive_option(self, "max_force", max_force)
        self.max_length = _positive_option(self, "max_length", max_length)
        self.min_length = _positive_option(self, "min_length", min_length)
        self.mass = mass
        if part_number is not None and (not isinstance(part_number, str) or not part_number.strip()):
            raise InputError(f"spring {name or ''}: part_number must be a non-empty string, got {part_number!r}")
        #: the catalogue part this spring is (a stock spring), or None
        self.part_number = part_number

    # ---------------------------------------------------------------- the law
    @abc.abstractmethod
    def tension(self, length: ValueT, parameters: Parameters) -> ValueT:
        """Tension ``F(L)`` [N], positive when the spring pulls its ends together."""

    @abc.abstractmethod
    def potential(self, length: ValueT, parameters: Parameters) -> ValueT:
        """Stored energy ``V_s(L)`` [J]."""

    def tension_per_length(self, length: ValueT, parameters: Parameters) -> ValueT:
        """``F(L) / L`` [N/m]; the force on end b is ``-(F/L) d`` with ``d = x_b - x_a``."""
        return self.tension(length, parameters) / length

    # ---------------------------------------------------------------- mass
    @property
    def mass(self) -> CoilMass | FixedMass | str | None:
        """``None``, :class:`FixedMass` or :class:`CoilMass` (a helical coil's: ``"coil"`` when it carries
        its own mass)."""
        return self._mass

    @mass.setter
    def mass(self, value: float | dict | CoilMass | FixedMass | None) -> None:
        self._mass = mass_from_record(value, f"{self._label()}: mass")
        coupled = isinstance(self._mass, CoilMass)
        if coupled:
            self._positive_stiffness("a mass coupled to the stiffness (m_s ∝ √k)")
        # m_s ∝ √k makes the torque nonlinear in k
        self.linear_parameters = tuple(
            key for key in type(self).linear_parameters if not (coupled and key == "stiffness")
        )

    @property
    def carries_mass(self) -> bool:
        """Whether the spring's own mass is part of the model (see :meth:`spring_mass`)."""
        return self._mass is not None

    def spring_mass(self, parameters: Parameters) -> Value:
        """``m_s`` [kg] for the given parameter values (0 without a mass)."""
        return 0.0 if self._mass is None else self._mass.value(parameters)

    def free_length_interval(self, lengths: np.ndarray) -> tuple[float, float]:
        """Free lengths ``(low, high)`` [m] for which this spring's own length constraints hold at
        the given sample lengths [m] (for a solver's start; ``(-inf, inf)`` when none apply)."""
        return -np.inf, np.inf

    # ---------------------------------------------------------------- element
    @property
    def routed(self) -> bool:
        """Whether a cable (over pulleys, or straight) joins the spring to ``b``."""
        return "cable_length" in self.parameters

    @property
    def anchors(self) -> dict[str, Anchor]:
        """The path's points in order: ``a``, the pulleys ``via1 …``, ``b``."""
        return {"a": self.a, **{f"via{i + 1}": pulley.anchor for i, pulley in enumerate(self.via)}, "b": self.b}

    @property
    def spring_ends(self) -> tuple[str, str]:
        """The ends of the spring's own body: ``a`` and the first pulley (``b`` when not routed over one)."""
        return ("a", "via1" if self.via else "b")

    @property
    def radii(self) -> tuple[float, ...]:
        """Pulley radius [m] at every point of the path (0 at the ends and at guide points)."""
        return (0.0, *(pulley.radius for pulley in self.via), 0.0)

    def check(self, mechanism: Mechanism) -> None:
        a, b = self.a, self.b
        for anchor in (a, b):
            mechanism.is_ground(anchor.body)  # raises InputError naming an unknown body
        for pulley in self.via:
            mechanism.is_ground(pulley.anchor.body)
        bodies = {anchor.body for anchor in self.anchors.values()}
        if self.via and (len(bodies) == 1 or all(mechanism.is_ground(body) for body in bodies)):
            raise InputError(
                f"spring {self.name!r}: every point of its path is on "
                f"{'body ' + repr(a.body) if len(bodies) == 1 else 'the ground'}; "
                "it cannot act on the mechanism"
            )
        if self.via:
            fixed = [(end, anchor) for end, anchor in self.anchors.items() if not anchor.is_free]
            for (end, first), (next_end, second) in zip(fixed, fixed[1:]):
                if (
                    first.body == second.body
                    and np.allclose(first.region().point([]), second.region().point([]))
                    and list(self.anchors).index(next_end) == list(self.anchors).index(end) + 1
                ):
                    raise InputError(
                        f"spring {self.name!r}: path points {end} and {next_end} coincide on body "
                        f"{first.body!r} at {first.region().point([]).tolist()} m; a segment needs "
                        "two distinct points"
                    )
        elif a.body == b.body or (mechanism.is_ground(a.body) and mechanism.is_ground(b.body)):
            where = f"body {a.body!r}" if a.body == b.body else f"the ground ({a.body!r}, {b.body!r})"
            raise InputError(f"spring {self.name!r}: both ends are on {where}; it cannot act on the mechanism")

    def contribution(self, sample: Sample, parameters: Parameters, points: dict) -> Contribution:
        if self.routed:
            return self._routed_contribution(sample, parameters, points)
        end_a, end_b = sample.point(self.a.body, points["a"]), sample.point(self.b.body, points["b"])
        d = end_b.position - end_a.position  # [m]
        length = (d.T @ d) ** 0.5  # L [m]
        force = self.tension_per_length(length, parameters) * d  # F u [N], pulls b towards a
        torque = end_b.generalized(force) - end_a.generalized(force)  # F (J_pb - J_pa)^T u
        square = getattr(self, "potential_of_square", None)  # a law smooth in L² (no √ at L = 0)
        potential = square(d.T @ d, parameters) if square is not None else self.potential(length, parameters)
        if self.carries_mass:
            half = 0.5 * self.spring_mass(parameters)  # [kg] at each end
            hold = -half * sample.gravity  # force that holds each half up [N]
            torque = torque + end_a.generalized(hold) + end_b.generalized(hold)
            potential = potential - half * (sample.gravity.T @ (end_a.position + end_b.position))  # [J]
        return Contribution(torque, potential, length, self.tension(length, parameters))

    def _routed_contribution(self, sample: Sample, parameters: Parameters, points: dict) -> Contribution:
        """``L = ℓ(path) − cable``; torque ``F Σ_i J_{P_i}^T ∂ℓ/∂P_i`` (see :mod:`springbalance.springs.routing`)."""
        ends = [sample.point(anchor.body, points[end]) for end, anchor in self.anchors.items()]
        path, gradients = path_length([end.position for end in ends], self.radii)  # [m], [1]
        length = path - parameters["cable_length"]  # L [m]
        tension = self.tension(length, parameters)  # F [N]
        torque = sample.zero()
        for end, gradient in zip(ends, gradients):
            torque = torque + end.generalized(tension * gradient)
        potential = self.potential(length, parameters)
        first, second = ends[0], ends[1]
        if self.carries_mass:
            half = 0.5 * self.spring_mass(parameters)
            hold = -half * sample.gravity
            torque = torque + first.generalized(hold) + second.generalized(hold)
            potential = potential - half * (sample.gravity.T @ (first.position + second.position))
        d = second.position - first.position
        return Contribution(torque, potential, length, tension, {"segment": (d.T @ d) ** 0.5})

    # ---------------------------------------------------------------- constraints and records
    def constraints(self) -> list:
        rows: list[practical.Constraint] = [practical.FitsSegment()] if self.routed else []
        if self.max_force is not None:
            rows.append(practical.MaxForce(self.max_force))
        if self.max_length is not None:
            rows.append(practical.MaxLength(self.max_length))
        if self.min_length is not None:
            rows.append(practical.MinLength(self.min_length))
        return rows

    def ends_to_dict(self) -> dict:
        return {end: anchor.to_dict() for end, anchor in (("a", self.a), ("b", self.b))}

    def to_dict(self) -> dict:
        """The record; a routed spring's is ``{name, type: routed, path, spring: {the law's record}, cable_length}``."""
        record = super().to_dict()
        if not self.routed:
            return record
        cable = record.pop("cable_length")
        name = record.pop("name")
        for end in ("a", "b"):
            record.pop(end)
        path = [self.a.to_dict(), *(pulley.to_dict() for pulley in self.via), self.b.to_dict()]
        return {"name": name, "type": "routed", "path": path, "spring": record, "cable_length": cable}

    def options(self) -> dict:
        limits = (("max_force", self.max_force), ("max_length", self.max_length), ("min_length", self.min_length))
        record: dict[str, Any] = {key: value for key, value in limits if value is not None}
        if self._mass is not None:
            record["mass"] = self._mass.to_dict()
        if self.part_number is not None:
            record["part_number"] = self.part_number
        return record

    # ---------------------------------------------------------------- how other tools express the law
    def tendon_law(self, values: dict, lengths: np.ndarray) -> tuple[float, float, float]:
        """The law as MuJoCo's linear tendon: ``(k [N/m], c [N], deviation [N])`` with ``F(L) ≈ k L + c``.

        ``values``: the parameter values [SI]; ``lengths``: the spring's lengths over the workspace
        [m]. A linear law is exact (``deviation`` 0); a nonlinear one returns its least-squares line
        over ``lengths`` and the largest ``|F(L) - (k L + c)|`` there.
        """
        lengths = np.asarray(lengths, dtype=float)
        forces = np.asarray(self.tension(lengths, values), dtype=float) * np.ones_like(lengths)  # [N]
        design = np.column_stack([lengths, np.ones_like(lengths)])
        (slope, constant), *_ = np.linalg.lstsq(design, forces, rcond=None)
        deviation = float(np.max(np.abs(design @ [slope, constant] - forces))) if lengths.size else 0.0
        return float(slope), float(constant), deviation

    def law_warnings(self, values: dict, lengths: np.ndarray, tolerance: float = 1e-6) -> list[str]:
        """Where a real part departs from this idealised two-sided law at the workspace ``lengths`` [m].

        The base class checks the length range (``min_length`` / ``max_length``: the law does not
        stop there); each law adds its own cases (a slack extension spring, a gas spring at its stop).
        """
        warnings = []
        if self.min_length is not None or self.max_length is not None:
            low = self.min_length if self.min_length is not None else -np.inf
            high = self.max_length if self.max_length is not None else np.inf
            outside = int(np.sum((lengths < low - tolerance) | (lengths > high + tolerance)))
            if outside:
                warnings.append(
                    f"spring {self.name!r} ({self.kind}) leaves its length range [{low:.6g}, {high:.6g}] m at "
                    f"{outside} of {lengths.size} workspace samples: the exported law does not stop at the ends "
                    "of the range"
                )
        return warnings

    def __repr__(self) -> str:
        via = "".join(f" -> {pulley!r}" for pulley in self.via)
        return f"{type(self).__name__}({self.name!r}, {self.a!r}{via} -> {self.b!r})"


class HelicalSpringMixin:
    """Mixin: the ``helical`` option (a helical spring of a given material and index must exist)."""

    helical_kind: ClassVar[str | None] = "extension"
    helical: Helical | None

    if TYPE_CHECKING:  # what the mixin uses of the spring it is mixed into (TwoPointSpring's)

        def _label(self) -> str: ...

        def _positive_stiffness(self, reason: str) -> None: ...

    def _set_helical(self, helical: Helical | dict | None) -> None:
        self.helical = None if helical is None else helical_from_dict(helical, f"{self._label()}: helical")
        if self.helical is not None:
            self._positive_stiffness("the helical option")

    def _helical_constraints(self) -> list:
        if self.helical is None:
            return []
        kind = self.helical_kind
        assert kind is not None  # a law with a helical option names its coil's kind
        return [practical.HelicalSpringExists(self.helical, kind)]
