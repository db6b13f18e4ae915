r"""Forces along a fixed direction (docs/model.md §3.11): a constant force or a gas spring on a slider.

On a slider or cross mechanism the force's line of action does not turn with the line between two
anchors: a block that carries a point ``p`` of body ``b`` slides along a straight guide fixed to
body ``c`` (``guide``, the world by default), and the element pushes the block along the guide's
unit vector ``u`` (``direction``, in the frame of ``c``). Its state is the stroke

.. math:: s = u_w \cdot (p_w - o_c) \quad [m],\qquad u_w = R_c\,u,

the anchor's position along the guide measured from the origin ``o_c`` of the guide's frame,
and it stores a potential ``V(s)`` [J]. The force on the anchor along ``u`` is
``f = -dV/ds`` [N] (the guide takes the reaction), and the element's share of the holding torque
is

.. math:: \tau = \frac{dV}{ds}\,\frac{\partial s}{\partial q}
          = -f\,\bigl[(J_p - J_{o})^T u_w + (J_{o+u} - J_{o})^T (p_w - o_c)\bigr],

where ``J_x`` is the Jacobian of a body-fixed point (``o`` and ``o + u`` are points of ``c``; on
the ground their Jacobians vanish and ``τ = J_p^T (-f u)``: a force ``f u`` at ``p`` has the
generalised force ``J_p^T (f u)`` and the potential ``-f u·p``). The second term is the moment of
the reaction on a moving guide.

Laws: :class:`DirectedForce` (``type: directed_force``, ``f = F0``: a pneumatic cylinder on a
large reservoir, a constant-force spool on a slider) and :class:`DirectedGas` (``type:
directed_gas``, a gas spring along the guide). Options: ``direction`` (required, a unit
3-vector [1]), ``guide`` (a body name; default ``universe``), ``max_force`` [N] (``|f| ≤``).
"""

from __future__ import annotations

import abc
from typing import TYPE_CHECKING, Annotated, Any, ClassVar

import annotated_types
import numpy as np

from springbalance.errors import InputError
from springbalance.springs import constraints as practical
from springbalance.springs.laws.spring import Contribution, PositiveNumber, Sample, Spring, _positive_option
from springbalance.springs.params import Anchor
from springbalance.springs.values import Parameters, ValueT

if TYPE_CHECKING:
    from springbalance.model.mechanism import Mechanism

#: the world's body name (a guide fixed to the ground)
WORLD = "universe"
#: how far from 1 the norm of ``direction`` may be (it is then normalised)
UNIT_TOLERANCE = 1e-6
#: the config type of ``direction``: three numbers
Direction = Annotated[list[float], annotated_types.Len(3, 3)]


class DirectedSpring(Spring):
    """An element that pushes a point of one body along a fixed direction of another (see the module)."""

    ends = ("a",)
    option_types = {
        "direction": Direction,
        "guide": str,
        "max_force": PositiveNumber | None,
    }
    option_descriptions: ClassVar[dict[str, str]] = {
        "direction": "unit vector u [1] of the guide, in the guide's frame: the force acts along it",
        "guide": "the body whose frame holds the direction (the slider's guide); default universe, the world",
        "max_force": "|f| ≤ max_force [N] at every sample",
    }
    required_options = ("direction",)
    state_quantity = ("stroke", "m")
    force_quantity = ("force along direction", "N")

    def __init__(
        self,
        a: Anchor,
        name: str | None = None,
        *,
        direction: Any = None,
        guide: str = WORLD,
        max_force: float | None = None,
        **parameters: Any,
    ):
        if not isinstance(a, Anchor):
            raise InputError(f"spring {name or ''!s}: its end must be an Anchor, got {a!r}")
        if not isinstance(guide, str) or not guide:
            raise InputError(f"spring {name or ''!s}: guide must be a body name, got {guide!r}")
        self.a, self.guide = a, guide
        self.direction = _unit(direction, f"spring {name or ''!s}: direction")
        super().__init__(name, **parameters)
        self.max_force = _positive_option(self, "max_force", max_force)

    # ---------------------------------------------------------------- the law
    @abc.abstractmethod
    def potential(self, stroke: ValueT, parameters: Parameters) -> ValueT:
        """Stored energy ``V(s)`` [J]."""

    @abc.abstractmethod
    def force(self, stroke: ValueT, parameters: Parameters) -> ValueT:
        """Force on the anchor along the direction, ``f = -dV/ds`` [N]."""

    @abc.abstractmethod
    def actuator_bias(self, values: dict) -> tuple[float, float]:
        """The law as ``f = f0 + f1 s`` ([N], [N/m]): exact for the affine laws of this module (MuJoCo's affine bias)."""

    # ---------------------------------------------------------------- element
    @property
    def anchors(self) -> dict[str, Anchor]:
        return {"a": self.a}

    @property
    def bodies(self) -> tuple[str, ...]:
        return (self.a.body, self.guide)

    def check(self, mechanism: Mechanism) -> None:
        ground = mechanism.is_ground(self.a.body)  # raises InputError naming an unknown body
        try:
            guide_ground = mechanism.is_ground(self.guide)
        except InputError as error:
            raise InputError(f"spring {self.name!r}: guide: {error}") from None
        if self.a.body == self.guide or (ground and guide_ground):
            where = (
                f"body {self.guide!r}" if self.a.body == self.guide else f"the ground ({self.a.body!r}, {self.guide!r})"
            )
            raise InputError(
                f"spring {self.name!r}: its anchor and its guide are both on {where}; it cannot act on the mechanism"
            )

    def contribution(self, sample: Sample, parameters: Parameters, points: dict) -> Contribution:
        end = sample.point(self.a.body, points["a"])
        origin = sample.point(self.guide, np.zeros((3, 1)))
        tip = sample.point(self.guide, self.direction.reshape(3, 1))
        unit = tip.position - origin.position  # u_w [1]
        lever = end.position - origin.position  # p_w - o_c [m]
        stroke = unit.T @ lever  # s [m]
        force = self.force(stroke, parameters)  # f [N] along u
        ds_dq = end.generalized(unit) - origin.generalized(unit) + tip.generalized(lever) - origin.generalized(lever)
        return Contribution(-force * ds_dq, self.potential(stroke, parameters), stroke, force)

    # ---------------------------------------------------------------- constraints and records
    def constraints(self) -> list:
        return [] if self.max_force is None else [practical.MaxForce(self.max_force)]

    def options(self) -> dict:
        record: dict[str, Any] = {"direction": [float(value) for value in self.direction], "guide": self.guide}
        if self.max_force is not None:
            record["max_force"] = self.max_force
        return record

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}({self.name!r}, {self.a!r}, direction={self.direction.tolist()} in {self.guide!r})"
        )


class DirectedForce(DirectedSpring):
    r"""Constant force along a fixed direction (a pneumatic cylinder on a large reservoir on a slider):

    .. math:: f = F_0,\qquad V = -F_0\, s .

    Parameter: ``force`` F0 [N], positive when it pushes the anchor along ``direction``.
    """

    kind = "directed_force"
    parameter_units = {"force": "N"}
    linear_parameters = ("force",)

    def potential(self, stroke: ValueT, parameters: Parameters) -> ValueT:
        return -parameters["force"] * stroke  # [N]·[m] = [J]

    def force(self, stroke: ValueT, parameters: Parameters) -> ValueT:
        return parameters["force"] + 0 * stroke  # [N]

    def actuator_bias(self, values: dict) -> tuple[float, float]:
        return float(values["force"]), 0.0


class DirectedGas(DirectedSpring):
    r"""Gas spring along a fixed direction: the law of a gas spring, with its length the stroke ``s``:

    .. math:: f = F_0 + k (l_0 - s),\qquad V = F_0 (l_0 - s) + k (l_0 - s)^2 / 2 .

    It pushes the anchor along ``direction`` with ``F0`` [N] at ``s = l0`` (``free_length`` [m],
    its extended position along the guide) and with the progression ``k`` [N/m] as it is
    compressed. Options: ``stays_compressed`` (default true: ``s ≤ l0``), ``stroke`` [m]
    (``s ≥ l0 - stroke``), and those of every directed element.
    """

    kind = "directed_gas"
    parameter_units = {"stiffness": "N/m", "free_length": "m", "preload": "N"}
    nonnegative = ("stiffness", "preload")
    defaults = {"preload": 0.0}
    linear_parameters = ("stiffness", "preload")
    option_types = {**DirectedSpring.option_types, "stays_compressed": bool, "stroke": PositiveNumber | None}

    def __init__(
        self, a: Anchor, name: str | None = None, *, stays_compressed: bool = True, stroke: Any = None, **kwargs: Any
    ):
        super().__init__(a, name, **kwargs)
        self.stays_compressed = bool(stays_compressed)
        self.stroke = _positive_option(self, "stroke", stroke)

    def potential(self, stroke: ValueT, parameters: Parameters) -> ValueT:
        compression = parameters["free_length"] - stroke  # [m]
        return compression * (parameters["preload"] + 0.5 * parameters["stiffness"] * compression)  # [J]

    def force(self, stroke: ValueT, parameters: Parameters) -> ValueT:
        return parameters["preload"] + parameters["stiffness"] * (parameters["free_length"] - stroke)  # [N]

    def actuator_bias(self, values: dict) -> tuple[float, float]:
        k = float(values["stiffness"])
        return float(values["preload"]) + k * float(values["free_length"]), -k

    def constraints(self) -> list:
        rows = super().constraints()
        if self.stays_compressed:
            rows.insert(0, practical.StaysCompressed())
        if self.stroke is not None:
            rows.append(practical.Stroke(self.stroke))
        return rows

    def options(self) -> dict:
        record = {**super().options(), "stays_compressed": self.stays_compressed}
        if self.stroke is not None:
            record["stroke"] = self.stroke
        return record


def _unit(direction: Any, where: str) -> np.ndarray:
    """``direction`` as a unit 3-vector (its norm within :data:`UNIT_TOLERANCE` of 1, then normalised)."""
    try:
        vector = np.asarray(direction, dtype=float)
    except (TypeError, ValueError):
        vector = np.zeros(0)
    if vector.shape != (3,) or not np.all(np.isfinite(vector)):
        raise InputError(f"{where}: expected a unit 3-vector [x, y, z], got {direction!r}")
    norm = float(np.linalg.norm(vector))
    if abs(norm - 1.0) > UNIT_TOLERANCE:
        raise InputError(f"{where}: expected a unit vector, got {vector.tolist()} (norm {norm:.6g})")
    return vector / norm
