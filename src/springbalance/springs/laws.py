r"""Springs (MODEL.md §2–4). Each law is one small class.

Every spring is an *element* that adds its share to the holding torque and the potential at
each workspace sample (:meth:`Spring.contribution`):

- **two-point springs** (:class:`TwoPointSpring`) join a point of body A to a point of body
  B (:class:`~springbalance.springs.params.Anchor`). With ``L`` the distance between the ends, the
  spring stores ``V_s(L)`` [J] and pulls the ends together with tension ``F(L) = dV_s/dL``
  [N] (negative for a spring that pushes). Its share of the actuator torque is

  .. math:: \tau_s(q) = F(L)\,(J_{p_b} - J_{p_a})^T u,\qquad u = (x_b - x_a)/L .

  A two-point spring may carry its own mass ``m_s`` (MODEL.md §4), fixed or coupled to its
  rate through the coil geometry (:class:`CoilMass`), as a uniform body between its ends:
  half at each end, which adds :math:`-(m_s/2)(J_{p_a} + J_{p_b})^T g` to the torque and
  :math:`-(m_s/2)\,g \cdot (x_a + x_b)` to the potential (``g`` the gravity vector).
- **torsional springs** (:class:`TorsionalSpring`) act on one revolute joint ``i``:
  :math:`V = k (q_i - q_0)^2/2 + \tau_0 (q_i - q_0)`, torque :math:`(k (q_i - q_0) + \tau_0)\,e_i`.

Laws are written with plain arithmetic, so one implementation serves CasADi symbols
(inside the optimiser) and NumPy arrays (checks, reports). ``parameters`` maps each
parameter name to its value. Every parameter is a number or :class:`~springbalance.springs.params.Free`.
Each element reports one *state* and one *generalised force* per sample: length [m] and
tension [N] for two-point springs, joint angle [rad] and torque [N·m] for torsional ones.
"""

from __future__ import annotations

import abc
import dataclasses
import math
from typing import ClassVar

import numpy as np

from springbalance.springs import constraints as practical
from springbalance.errors import InputError
from springbalance.springs.params import Anchor, Free
from springbalance.springs.sizing import coil_mass, helical_from_dict, material_named


@dataclasses.dataclass
class Contribution:
    """What one spring adds at one sample (CasADi expressions).

    Attributes:
        torque: its share of the holding torque ``∂V_s/∂q`` (nv) [N·m or N].
        potential: its potential energy [J] (elastic, plus the gravity of its own mass).
        state: length ``L`` [m] (two-point springs) or joint angle ``q_i`` [rad] (torsional).
        force: ``dV_s/d(state)``: tension [N] or torque [N·m].
    """

    torque: object
    potential: object
    state: object
    force: object


class Spring(abc.ABC):
    """Base class of every spring element. Subclasses set ``kind``, ``parameter_units`` and the law.

    The per-sample ``sample`` object handed to :meth:`contribution` is built by
    :class:`~springbalance.design.torque_model.TorqueModel`; it gives ``sample.point(body, p)`` (world
    position of a body-fixed point and its ``J_p^T f`` product), ``sample.coordinate(joint)``
    (the joint's coordinate), ``sample.direction(joint)`` (the unit torque vector ``e_i``),
    ``sample.zero()`` (an nv zero vector) and ``sample.gravity`` (the gravity vector [m/s²]).
    """

    kind: ClassVar[str] = ""
    #: parameter name -> unit; order is the order of design variables.
    parameter_units: ClassVar[dict[str, str]] = {}
    #: parameters that must be ≥ 0.
    nonnegative: ClassVar[tuple[str, ...]] = ()
    defaults: ClassVar[dict[str, float]] = {}
    #: parameters that the torque and the potential depend on linearly (the solver fits them
    #: exactly by linear least squares at every start). An instance may narrow this list.
    linear_parameters: ClassVar[tuple[str, ...]] = ()
    #: record keys of the options (besides name, type, ends/joint and parameters).
    option_keys: ClassVar[tuple[str, ...]] = ()
    #: what the per-sample state and generalised force are, for reports: (name, unit).
    state_quantity: ClassVar[tuple[str, str]] = ("length", "m")
    force_quantity: ClassVar[tuple[str, str]] = ("tension", "N")

    def __init__(self, name: str | None = None, **parameters):
        self.name = name
        unknown = set(parameters) - set(self.parameter_units)
        if unknown:
            raise InputError(f"{type(self).__name__} {name or ''}: unknown parameter(s) {', '.join(sorted(unknown))}; "
                             f"valid: {', '.join(self.parameter_units)}")
        self.parameters: dict[str, float | Free] = {}
        for key in self.parameter_units:
            value = parameters.get(key, self.defaults.get(key))
            if value is None:
                raise InputError(f"{type(self).__name__} {name or ''}: parameter {key!r} is required")
            self.parameters[key] = _checked_parameter(self, key, value)

    # ---------------------------------------------------------------- what the element needs
    @property
    def anchors(self) -> dict[str, Anchor]:
        """Ends with (possibly free) anchor points, by end name (``{}`` for torsional springs)."""
        return {}

    @property
    def bodies(self) -> tuple[str, ...]:
        """Bodies whose placement and Jacobian the element needs."""
        return tuple(anchor.body for anchor in self.anchors.values())

    @property
    def joints(self) -> tuple[str, ...]:
        """Joints whose coordinate the element needs."""
        return ()

    def check(self, mechanism) -> None:
        """Raise :class:`~springbalance.errors.InputError` when the element does not fit ``mechanism``."""

    @abc.abstractmethod
    def contribution(self, sample, parameters: dict, points: dict) -> Contribution:
        """Torque, potential, state and generalised force at one sample.

        ``parameters`` maps parameter names to numbers or CasADi symbols; ``points`` maps each
        end of :attr:`anchors` to its body-frame point (3-vector, affine in the design variables).
        """

    # ---------------------------------------------------------------- constraints and records
    def constraints(self) -> list:
        """Practical constraints (MODEL.md §6) that apply to this spring."""
        return []

    def options(self) -> dict:
        return {}

    def ends_to_dict(self) -> dict:
        return {end: anchor.to_dict() for end, anchor in self.anchors.items()}

    def to_dict(self) -> dict:
        record = {"name": self.name, "type": self.kind, **self.ends_to_dict()}
        for key, value in self.parameters.items():
            record[key] = value.to_dict() if isinstance(value, Free) else float(value)
        record.update(self.options())
        return record

    def _label(self) -> str:
        return f"{type(self).__name__} {self.name or ''}".strip()

    def _positive_stiffness(self, reason: str) -> None:
        """Reject a stiffness range that reaches 0 (``reason`` says what needs k > 0)."""
        stiffness = self.parameters["stiffness"]
        lowest = float(stiffness.lower) if isinstance(stiffness, Free) else float(stiffness)
        if lowest <= 0:
            raise InputError(f"{self._label()}: {reason} needs a stiffness > 0 (its lower bound is {lowest:g}); "
                             "give stiffness a positive lower bound")


# ---------------------------------------------------------------------- spring mass
class CoilMass:
    r"""Mass of a helical spring whose wire diameter follows its rate (MODEL.md §4).

    A coil of fixed mean diameter ``D`` [m] and ``n`` active coils has rate
    :math:`k = G d^4 / (8 D^3 n)`; its wire of length ``L_w`` [m] weighs

    .. math:: m_s = \rho \pi L_w \sqrt{D^3 n k / (2 G)}  \quad [kg],

    so a stiffer spring of the same geometry is heavier. ``shear_modulus`` G [Pa] and
    ``density`` rho [kg/m³] come from ``material`` (see :data:`springbalance.springs.sizing.MATERIALS`)
    unless given. ``wire_length`` defaults to :math:`\pi D (n + 2)` (two end coils or hooks).
    """

    def __init__(self, coil_diameter: float, active_coils: float, wire_length: float | None = None,
                 material: str | None = None, shear_modulus: float | None = None, density: float | None = None):
        self.material = None if material is None else material_named(material).name
        if material is not None:
            found = material_named(material)
            shear_modulus = found.shear_modulus if shear_modulus is None else shear_modulus
            density = found.density if density is None else density
        if shear_modulus is None or density is None:
            raise InputError("CoilMass needs shear_modulus and density, or a material")
        values = {"coil_diameter": coil_diameter, "active_coils": active_coils, "shear_modulus": shear_modulus,
                  "density": density}
        if wire_length is not None:
            values["wire_length"] = wire_length
        for key, value in values.items():
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
                    or not np.isfinite(value) or value <= 0:
                raise InputError(f"CoilMass {key} must be a positive number, got {value!r}")
        self.coil_diameter, self.active_coils = float(coil_diameter), float(active_coils)       # [m], [1]
        self.shear_modulus, self.density = float(shear_modulus), float(density)                 # [Pa], [kg/m³]
        self.wire_length = (float(wire_length) if wire_length is not None
                            else math.pi * self.coil_diameter * (self.active_coils + 2))       # [m]

    couples_stiffness = True

    def value(self, parameters):
        """``m_s`` [kg] for the spring's parameter values (uses ``stiffness``)."""
        return coil_mass(parameters["stiffness"], self.coil_diameter, self.active_coils, self.wire_length,
                         self.shear_modulus, self.density)

    def wire_diameter(self, stiffness):
        """``d = (8 D³ n k / G)^(1/4)`` [m]."""
        return (8 * self.coil_diameter**3 * self.active_coils * stiffness / self.shear_modulus) ** 0.25

    def to_dict(self) -> dict:
        record = {"coil_diameter": self.coil_diameter, "active_coils": self.active_coils,
                  "wire_length": self.wire_length, "shear_modulus": self.shear_modulus, "density": self.density}
        if self.material is not None:
            record["material"] = self.material
        return record

    def __repr__(self) -> str:
        return (f"CoilMass(D={self.coil_diameter}, n={self.active_coils}, L_w={self.wire_length}, "
                f"G={self.shear_modulus:g}, rho={self.density:g})")


class FixedMass:
    """A spring mass that does not depend on the design [kg]."""

    couples_stiffness = False

    def __init__(self, mass: float):
        if isinstance(mass, bool) or not isinstance(mass, (int, float, np.floating, np.integer)) \
                or not np.isfinite(mass) or mass < 0:
            raise InputError(f"spring mass must be a number ≥ 0 [kg], got {mass!r}")
        self.mass = float(mass)

    def value(self, parameters):
        return self.mass

    def to_dict(self) -> float:
        return self.mass

    def __repr__(self) -> str:
        return f"FixedMass({self.mass})"


_COIL_MASS_KEYS = ("coil_diameter", "active_coils", "wire_length", "material", "shear_modulus", "density")


def mass_from_record(value, where: str = "mass"):
    """``m`` [kg] (fixed) or ``{coil_diameter, active_coils, wire_length?, material? | shear_modulus, density}``."""
    if value is None or isinstance(value, (FixedMass, CoilMass)):
        return value
    try:
        if isinstance(value, dict):
            unknown = [key for key in value if key not in _COIL_MASS_KEYS]
            if unknown:
                raise InputError(f"unknown key {unknown[0]!r}; valid keys: {', '.join(_COIL_MASS_KEYS)}")
            for key in ("coil_diameter", "active_coils"):
                if key not in value:
                    raise InputError(f"missing key {key!r}")
            return CoilMass(**value)
        return FixedMass(value)
    except InputError as error:
        raise InputError(f"{where}: {error}") from None


# ---------------------------------------------------------------------- two-point springs
class TwoPointSpring(Spring):
    """Base class of springs between two anchors (law ``F(L)``, ``V_s(L)``), with optional mass.

    Options: ``max_force`` [N] (``|F| ≤``), ``max_length`` / ``min_length`` [m], ``mass``:
    a number [kg] or a :class:`CoilMass` (or its record).
    """

    option_keys = ("max_force", "max_length", "min_length", "mass")

    def __init__(self, a: Anchor, b: Anchor, name: str | None = None, *, max_force: float | None = None,
                 max_length: float | None = None, min_length: float | None = None, mass=None, **parameters):
        if not isinstance(a, Anchor) or not isinstance(b, Anchor):
            raise InputError(f"spring {name or ''!s}: ends must be Anchor objects, got {a!r} and {b!r}")
        self.a, self.b = a, b
        super().__init__(name, **parameters)
        self.max_force = _positive_option(self, "max_force", max_force)
        self.max_length = _positive_option(self, "max_length", max_length)
        self.min_length = _positive_option(self, "min_length", min_length)
        self.mass = mass

    # ---------------------------------------------------------------- the law
    @abc.abstractmethod
    def tension(self, length, parameters):
        """Tension ``F(L)`` [N], positive when the spring pulls its ends together."""

    @abc.abstractmethod
    def potential(self, length, parameters):
        """Stored energy ``V_s(L)`` [J]."""

    def tension_per_length(self, length, parameters):
        """``F(L) / L`` [N/m]; the force on end b is ``-(F/L) d`` with ``d = x_b - x_a``."""
        return self.tension(length, parameters) / length

    # ---------------------------------------------------------------- mass
    @property
    def mass(self):
        """``None``, :class:`FixedMass` or :class:`CoilMass`."""
        return self._mass

    @mass.setter
    def mass(self, value) -> None:
        self._mass = mass_from_record(value, f"{self._label()}: mass")
        coupled = isinstance(self._mass, CoilMass)
        if coupled:
            self._positive_stiffness("a mass coupled to the stiffness (m_s ∝ √k)")
        # m_s ∝ √k makes the torque nonlinear in k
        self.linear_parameters = tuple(key for key in type(self).linear_parameters
                                       if not (coupled and key == "stiffness"))

    def spring_mass(self, parameters):
        """``m_s`` [kg] for the given parameter values (0 without a mass)."""
        return 0.0 if self._mass is None else self._mass.value(parameters)

    def free_length_interval(self, lengths) -> tuple[float, float]:
        """Free lengths ``(low, high)`` [m] for which this spring's own length constraints hold at
        the given sample lengths [m] (for a solver's start; ``(-inf, inf)`` when none apply)."""
        return -np.inf, np.inf

    # ---------------------------------------------------------------- element
    @property
    def anchors(self) -> dict[str, Anchor]:
        return {"a": self.a, "b": self.b}

    def check(self, mechanism) -> None:
        a, b = self.a, self.b
        for anchor in (a, b):
            mechanism.is_ground(anchor.body)  # raises InputError naming an unknown body
        if a.body == b.body or (mechanism.is_ground(a.body) and mechanism.is_ground(b.body)):
            where = f"body {a.body!r}" if a.body == b.body else f"the ground ({a.body!r}, {b.body!r})"
            raise InputError(f"spring {self.name!r}: both ends are on {where}; it cannot act on the mechanism")

    def contribution(self, sample, parameters, points) -> Contribution:
        end_a, end_b = sample.point(self.a.body, points["a"]), sample.point(self.b.body, points["b"])
        d = end_b.position - end_a.position                     # [m]
        length = (d.T @ d) ** 0.5                                # L [m]
        force = self.tension_per_length(length, parameters) * d  # F u [N], pulls b towards a
        torque = end_b.generalized(force) - end_a.generalized(force)   # F (J_pb - J_pa)^T u
        potential = self.potential(length, parameters)
        if self._mass is not None:
            half = 0.5 * self.spring_mass(parameters)            # [kg] at each end
            hold = -half * sample.gravity                        # force that holds each half up [N]
            torque = torque + end_a.generalized(hold) + end_b.generalized(hold)
            potential = potential - half * (sample.gravity.T @ (end_a.position + end_b.position))  # [J]
        return Contribution(torque, potential, length, self.tension(length, parameters))

    # ---------------------------------------------------------------- constraints and records
    def constraints(self) -> list:
        rows = []
        if self.max_force is not None:
            rows.append(practical.MaxForce(self.max_force))
        if self.max_length is not None:
            rows.append(practical.MaxLength(self.max_length))
        if self.min_length is not None:
            rows.append(practical.MinLength(self.min_length))
        return rows

    def options(self) -> dict:
        record = {key: value for key, value in (("max_force", self.max_force), ("max_length", self.max_length),
                                                ("min_length", self.min_length)) if value is not None}
        if self._mass is not None:
            record["mass"] = self._mass.to_dict()
        return record

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, {self.a!r} -> {self.b!r})"


class _HelicalOption:
    """Mixin: the ``helical`` option (a helical spring of a given material and index must exist)."""

    helical_kind: ClassVar[str] = "extension"

    def _set_helical(self, helical) -> None:
        self.helical = None if helical is None else helical_from_dict(helical, f"{self._label()}: helical")
        if self.helical is not None:
            self._positive_stiffness("the helical option")

    def _helical_constraints(self) -> list:
        if self.helical is None:
            return []
        return [practical.HelicalSpringExists(self.helical, self.helical_kind)]


class ZeroFreeLengthSpring(TwoPointSpring):
    r"""Zero-free-length spring: :math:`F = k L`, :math:`V_s = k L^2 / 2`.

    Parameters: ``stiffness`` k [N/m].
    """

    kind = "zero_free_length"
    parameter_units = {"stiffness": "N/m"}
    nonnegative = ("stiffness",)
    linear_parameters = ("stiffness",)

    def tension(self, length, parameters):
        return parameters["stiffness"] * length                       # [N/m]·[m] = [N]

    def potential(self, length, parameters):
        return 0.5 * parameters["stiffness"] * length * length        # [N/m]·[m²] = [J]

    def tension_per_length(self, length, parameters):
        return parameters["stiffness"] + 0 * length                   # smooth at L = 0


class ExtensionSpring(_HelicalOption, TwoPointSpring):
    r"""Linear extension spring with initial tension:

    .. math:: F = F_0 + k (L - l_0),\qquad V_s = F_0 (L - l_0) + k (L - l_0)^2 / 2 .

    Parameters: ``stiffness`` k [N/m], ``free_length`` l0 [m], ``initial_tension`` F0 [N]
    (default 0). Options: ``keep_tension`` (default True: ``L ≥ l0`` at every sample, a
    coil spring cannot be compressed below its free length), ``max_stretch`` ratio ρ
    (``L ≤ ρ l0``), ``max_force`` [N], ``max_length`` / ``min_length`` [m], ``mass``, and
    ``helical`` (:class:`~springbalance.springs.sizing.Helical`: a helical extension spring of that
    material and index with hooks must fit the free length and carry the force).
    """

    kind = "extension"
    parameter_units = {"stiffness": "N/m", "free_length": "m", "initial_tension": "N"}
    nonnegative = ("stiffness", "free_length", "initial_tension")
    defaults = {"initial_tension": 0.0}
    linear_parameters = ("stiffness", "initial_tension")
    option_keys = TwoPointSpring.option_keys + ("keep_tension", "max_stretch", "helical")
    helical_kind = "extension"

    def __init__(self, a: Anchor, b: Anchor, name: str | None = None, *, keep_tension: bool = True,
                 max_stretch: float | None = None, helical=None, **kwargs):
        super().__init__(a, b, name, **kwargs)
        self.keep_tension = bool(keep_tension)
        self.max_stretch = _positive_option(self, "max_stretch", max_stretch)
        if self.max_stretch is not None and self.max_stretch <= 1:
            raise InputError(f"spring {name or ''}: max_stretch is a ratio L/l0 and must exceed 1, got {max_stretch}")
        self._set_helical(helical)

    def free_length_interval(self, lengths) -> tuple[float, float]:
        """``max L / ρ ≤ l0`` (stretch limit) and ``l0 ≤ min L`` (stays in tension)."""
        low = float(np.max(lengths)) / self.max_stretch if self.max_stretch is not None else -np.inf
        high = float(np.min(lengths)) if self.keep_tension else np.inf
        return low, high

    def tension(self, length, parameters):
        stretch = length - parameters["free_length"]                          # [m]
        return parameters["initial_tension"] + parameters["stiffness"] * stretch  # [N]

    def potential(self, length, parameters):
        stretch = length - parameters["free_length"]                          # [m]
        return stretch * (parameters["initial_tension"] + 0.5 * parameters["stiffness"] * stretch)  # [J]

    def constraints(self) -> list:
        rows = super().constraints()
        if self.keep_tension:
            rows.insert(0, practical.StaysInTension())
        if self.max_stretch is not None:
            rows.append(practical.MaxStretch(self.max_stretch))
        return rows + self._helical_constraints()

    def options(self) -> dict:
        record = super().options()
        record["keep_tension"] = self.keep_tension
        if self.max_stretch is not None:
            record["max_stretch"] = self.max_stretch
        if self.helical is not None:
            record["helical"] = self.helical.to_dict()
        return record


class CompressionSpring(_HelicalOption, TwoPointSpring):
    r"""Compression spring: pushes its ends apart (negative tension), preload ``F0`` at length ``l0``:

    .. math:: F = -\bigl(F_0 + k (l_0 - L)\bigr),\qquad V_s = F_0 (l_0 - L) + k (l_0 - L)^2 / 2 .

    Parameters: ``stiffness`` k [N/m], ``free_length`` l0 [m] (the length at which it pushes
    with ``F0``: a coil's free length, a gas spring's extended length), ``preload`` F0 [N]
    (default 0). Options: ``stays_compressed`` (default True: ``L ≤ l0`` at every sample, the
    spring stays in contact), ``stroke`` [m] (``L ≥ l0 - stroke``: it cannot be compressed
    further), ``max_force``, ``max_length`` / ``min_length``, ``mass``, and ``helical`` (a helical
    compression spring of that material and index must carry the force without going solid).
    """

    kind = "compression"
    parameter_units = {"stiffness": "N/m", "free_length": "m", "preload": "N"}
    nonnegative = ("stiffness", "free_length", "preload")
    defaults = {"preload": 0.0}
    linear_parameters = ("stiffness", "preload")
    option_keys = TwoPointSpring.option_keys + ("stays_compressed", "stroke", "helical")
    helical_kind = "compression"

    def __init__(self, a: Anchor, b: Anchor, name: str | None = None, *, stays_compressed: bool = True,
                 stroke: float | None = None, helical=None, **kwargs):
        super().__init__(a, b, name, **kwargs)
        self.stays_compressed = bool(stays_compressed)
        self.stroke = _positive_option(self, "stroke", stroke)
        self._set_helical(helical)

    def free_length_interval(self, lengths) -> tuple[float, float]:
        """``max L ≤ l0`` (stays compressed) and ``l0 ≤ min L + stroke`` (stroke limit)."""
        low = float(np.max(lengths)) if self.stays_compressed else -np.inf
        high = float(np.min(lengths)) + self.stroke if self.stroke is not None else np.inf
        return low, high

    def tension(self, length, parameters):
        compression = parameters["free_length"] - length                          # [m]
        return -(parameters["preload"] + parameters["stiffness"] * compression)  # [N], pushes

    def potential(self, length, parameters):
        compression = parameters["free_length"] - length                          # [m]
        return compression * (parameters["preload"] + 0.5 * parameters["stiffness"] * compression)  # [J]

    def constraints(self) -> list:
        rows = super().constraints()
        if self.stays_compressed:
            rows.insert(0, practical.StaysCompressed())
        if self.stroke is not None:
            rows.append(practical.Stroke(self.stroke))
        return rows + self._helical_constraints()

    def options(self) -> dict:
        record = super().options()
        record["stays_compressed"] = self.stays_compressed
        if self.stroke is not None:
            record["stroke"] = self.stroke
        if self.helical is not None:
            record["helical"] = self.helical.to_dict()
        return record


class GasSpring(CompressionSpring):
    r"""Gas spring: the law of :class:`CompressionSpring`, preload ``F0`` at the extended length ``l0``,

    .. math:: F = -\bigl(F_0 + k (l_0 - L)\bigr),\qquad V_s = F_0 (l_0 - L) + k (l_0 - L)^2 / 2,

    where ``k`` [N/m] is the progression of the gas force over the stroke. It always stays
    compressed (``L ≤ l0``, option ``stays_compressed``); ``stroke`` [m] limits the compression
    (``L ≥ l0 - stroke``). No ``helical`` option.
    """

    kind = "gas"
    option_keys = TwoPointSpring.option_keys + ("stays_compressed", "stroke")
    helical_kind = None  # not a coil: nothing to size

    def __init__(self, a: Anchor, b: Anchor, name: str | None = None, **kwargs):
        if kwargs.get("helical") is not None:
            raise InputError(f"GasSpring {name or ''}: a gas spring has no helical option")
        super().__init__(a, b, name, **kwargs)


class ConstantForceSpring(TwoPointSpring):
    r"""Constant-force element (pneumatic spring on a large reservoir, cable on a constant-force spool):

    .. math:: F = F_0,\qquad V_s = F_0 L .

    Parameter: ``force`` F0 [N], positive when it pulls the ends together (a spool), negative
    when it pushes (a cylinder). Options as :class:`TwoPointSpring`; ``min_length`` /
    ``max_length`` give its stroke.
    """

    kind = "constant_force"
    parameter_units = {"force": "N"}
    linear_parameters = ("force",)

    def tension(self, length, parameters):
        return parameters["force"] + 0 * length                       # [N]

    def potential(self, length, parameters):
        return parameters["force"] * length                           # [N]·[m] = [J]


# ---------------------------------------------------------------------- torsional spring
class TorsionalSpring(Spring):
    r"""Torsional spring on a revolute (or continuous) joint ``i``:

    .. math:: V = \tfrac12 k (q_i - q_0)^2 + \tau_0 (q_i - q_0),\qquad
              \tau = \bigl(k (q_i - q_0) + \tau_0\bigr)\, e_i .

    Parameters: ``stiffness`` k [N·m/rad], ``neutral_angle`` q0 [rad], ``preload`` τ0 [N·m]
    (default 0). Options: ``max_torque`` [N·m] (``|k (q_i - q_0) + τ_0| ≤``),
    ``max_deflection`` [rad] (``|q_i - q_0| ≤``). Its state is the joint angle ``q_i`` [rad]
    and its generalised force the spring torque [N·m].
    """

    kind = "torsional"
    parameter_units = {"stiffness": "N·m/rad", "neutral_angle": "rad", "preload": "N·m"}
    nonnegative = ("stiffness",)
    defaults = {"preload": 0.0}
    linear_parameters = ("stiffness", "preload")
    option_keys = ("max_torque", "max_deflection")
    state_quantity = ("angle", "rad")
    force_quantity = ("torque", "N·m")

    def __init__(self, joint: str, name: str | None = None, *, max_torque: float | None = None,
                 max_deflection: float | None = None, **parameters):
        if not isinstance(joint, str) or not joint:
            raise InputError(f"TorsionalSpring {name or ''}: joint must be a joint name, got {joint!r}")
        self.joint = joint
        super().__init__(name, **parameters)
        self.max_torque = _positive_option(self, "max_torque", max_torque)
        self.max_deflection = _positive_option(self, "max_deflection", max_deflection)

    @property
    def joints(self) -> tuple[str, ...]:
        return (self.joint,)

    def check(self, mechanism) -> None:
        try:
            joint = mechanism.joint(self.joint)
        except InputError as error:
            raise InputError(f"torsional spring {self.name!r}: {error}") from None
        if joint.kind == "prismatic":
            raise InputError(f"torsional spring {self.name!r}: joint {self.joint!r} is prismatic; "
                             "a torsional spring needs a revolute or continuous joint")

    def torque(self, angle, parameters):
        """Spring torque ``k (q - q0) + τ0`` [N·m] at joint angle ``q`` [rad]."""
        return parameters["stiffness"] * (angle - parameters["neutral_angle"]) + parameters["preload"]

    def potential(self, angle, parameters):
        """Stored energy ``k (q - q0)²/2 + τ0 (q - q0)`` [J]."""
        deflection = angle - parameters["neutral_angle"]                      # [rad]
        return deflection * (parameters["preload"] + 0.5 * parameters["stiffness"] * deflection)  # [J]

    def contribution(self, sample, parameters, points) -> Contribution:
        angle = sample.coordinate(self.joint)                                 # q_i [rad]
        torque = self.torque(angle, parameters)                               # [N·m]
        return Contribution(sample.direction(self.joint) * torque, self.potential(angle, parameters), angle, torque)

    def constraints(self) -> list:
        rows = []
        if self.max_torque is not None:
            rows.append(practical.MaxTorque(self.max_torque))
        if self.max_deflection is not None:
            rows.append(practical.MaxDeflection(self.max_deflection))
        return rows

    def ends_to_dict(self) -> dict:
        return {"joint": self.joint}

    def options(self) -> dict:
        return {key: value for key, value in (("max_torque", self.max_torque), ("max_deflection", self.max_deflection))
                if value is not None}

    def __repr__(self) -> str:
        return f"TorsionalSpring({self.name!r}, joint={self.joint!r})"


#: spring ``type`` name in configs and saved designs -> class.
SPRING_TYPES: dict[str, type[Spring]] = {cls.kind: cls for cls in (
    ExtensionSpring, ZeroFreeLengthSpring, CompressionSpring, GasSpring, ConstantForceSpring, TorsionalSpring)}


def _checked_parameter(spring: Spring, key: str, value):
    label = f"{type(spring).__name__} {spring.name or ''}".strip()
    if isinstance(value, Free):
        if value.lower.shape != ():
            raise InputError(f"{label}: {key} must be a scalar Free, got bounds {value.lower.tolist()}")
        if key in spring.nonnegative and value.lower < 0:
            raise InputError(f"{label}: {key} lower bound must be ≥ 0, got {float(value.lower)}")
        return value
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{label}: {key} must be a number or Free, got {value!r}") from None
    if not np.isfinite(number):
        raise InputError(f"{label}: {key} must be finite, got {value!r}")
    if key in spring.nonnegative and number < 0:
        raise InputError(f"{label}: {key} must be ≥ 0, got {number}")
    return number


def _positive_option(spring: Spring, key: str, value):
    if value is None:
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"spring {spring.name or ''}: {key} must be a number, got {value!r}") from None
    if not np.isfinite(number) or number <= 0:
        raise InputError(f"spring {spring.name or ''}: {key} must be a positive number, got {value!r}")
    return number


_BOOLEAN_OPTIONS = ("keep_tension", "stays_compressed")


def spring_from_dict(record, where: str = "spring") -> Spring:
    """Build a spring from its record (as in configs and saved designs).

    Two-point springs: ``{name?, type, a: anchor, b: anchor, <parameters>, <options>}``;
    torsional springs: ``{name?, type: torsional, joint, <parameters>, <options>}``. Each
    parameter is a number or ``{lower, upper, init?}``; the options of each type are its
    class's ``option_keys``.
    """
    from springbalance.springs.params import anchor_from_dict, check_keys, value_from_record

    if not isinstance(record, dict):
        raise InputError(f"{where}: expected a mapping, got {record!r}")
    kind = record.get("type", "extension")
    if not isinstance(kind, str) or kind not in SPRING_TYPES:
        raise InputError(f"{where}.type: unknown spring type {kind!r}; valid: {', '.join(SPRING_TYPES)}")
    cls = SPRING_TYPES[kind]
    ends = ("joint",) if issubclass(cls, TorsionalSpring) else ("a", "b")
    check_keys(record, ("name", "type", *ends, *cls.parameter_units, *cls.option_keys), where)
    name = record.get("name")
    where = f"{where} {name!r}" if name else where
    for end in ends:
        if end not in record:
            raise InputError(f"{where}: missing key {end!r} (" +
                             ("the joint it acts on)" if end == "joint" else "the anchor of that end)"))
    parameters = {key: value_from_record(record[key], f"{where}.{key}") for key in cls.parameter_units if key in record}
    extra = {key: record[key] for key in cls.option_keys if key in record}
    for key in _BOOLEAN_OPTIONS:
        if key in extra and not isinstance(extra[key], bool):
            raise InputError(f"{where}.{key}: expected true or false, got {extra[key]!r}")
    if "mass" in extra:
        extra["mass"] = mass_from_record(extra["mass"], f"{where}.mass")
    if "helical" in extra:
        extra["helical"] = helical_from_dict(extra["helical"], f"{where}.helical")
    name = None if name is None else str(name)
    try:
        if ends == ("joint",):
            if not isinstance(record["joint"], str):
                raise InputError(f"joint: expected a joint name, got {record['joint']!r}")
            return cls(record["joint"], name, **parameters, **extra)
        a = anchor_from_dict(record["a"], f"{where}.a")
        b = anchor_from_dict(record["b"], f"{where}.b")
        return cls(a, b, name, **parameters, **extra)
    except InputError as error:
        if str(error).startswith(where):
            raise
        raise InputError(f"{where}: {error}") from None
