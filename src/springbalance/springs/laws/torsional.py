r"""Torsional spring on a revolute joint (docs/model.md §3.6)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from springbalance.errors import InputError
from springbalance.springs import constraints as practical
from springbalance.springs.laws.spring import Contribution, PositiveNumber, Sample, Spring, _positive_option
from springbalance.springs.values import Parameters, ValueT

if TYPE_CHECKING:
    from springbalance.model.mechanism import Mechanism


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
    ends = ("joint",)
    option_types = {"max_torque": PositiveNumber | None, "max_deflection": PositiveNumber | None}
    state_quantity = ("angle", "rad")
    force_quantity = ("torque", "N·m")

    def __init__(
        self,
        joint: str,
        name: str | None = None,
        *,
        max_torque: float | None = None,
        max_deflection: float | None = None,
        **parameters: Any,
    ):
        if not isinstance(joint, str) or not joint:
            raise InputError(f"TorsionalSpring {name or ''}: joint must be a joint name, got {joint!r}")
        self.joint = joint
        super().__init__(name, **parameters)
        self.max_torque = _positive_option(self, "max_torque", max_torque)
        self.max_deflection = _positive_option(self, "max_deflection", max_deflection)

    @property
    def joints(self) -> tuple[str, ...]:
        return (self.joint,)

    def check(self, mechanism: Mechanism) -> None:
        try:
            joint = mechanism.joint(self.joint)
        except InputError as error:
            raise InputError(f"torsional spring {self.name!r}: {error}") from None
        if joint.kind == "prismatic":
            raise InputError(
                f"torsional spring {self.name!r}: joint {self.joint!r} is prismatic; "
                "a torsional spring needs a revolute or continuous joint"
            )

    def torque(self, angle: ValueT, parameters: Parameters) -> ValueT:
        """Spring torque ``k (q - q0) + τ0`` [N·m] at joint angle ``q`` [rad]."""
        return parameters["stiffness"] * (angle - parameters["neutral_angle"]) + parameters["preload"]

    def potential(self, angle: ValueT, parameters: Parameters) -> ValueT:
        """Stored energy ``k (q - q0)²/2 + τ0 (q - q0)`` [J]."""
        deflection = angle - parameters["neutral_angle"]  # [rad]
        return deflection * (parameters["preload"] + 0.5 * parameters["stiffness"] * deflection)  # [J]

    def contribution(self, sample: Sample, parameters: Parameters, points: dict) -> Contribution:
        angle = sample.coordinate(self.joint)  # q_i [rad]
        torque = self.torque(angle, parameters)  # [N·m]
        return Contribution(sample.direction(self.joint) * torque, self.potential(angle, parameters), angle, torque)

    def constraints(self) -> list:
        rows: list[practical.Constraint] = []
        if self.max_torque is not None:
            rows.append(practical.MaxTorque(self.max_torque))
        if self.max_deflection is not None:
            rows.append(practical.MaxDeflection(self.max_deflection))
        return rows

    def ends_to_dict(self) -> dict:
        return {"joint": self.joint}

    def options(self) -> dict:
        return {
            key: value
            for key, value in (("max_torque", self.max_torque), ("max_deflection", self.max_deflection))
            if value is not None
        }

    def __repr__(self) -> str:
        return f"TorsionalSpring({self.name!r}, joint={self.joint!r})"
