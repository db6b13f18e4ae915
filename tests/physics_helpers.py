"""Independent physics for the tests: total potential energy from Pinocchio alone.

Nothing here imports springbalance's torque model. The holding torque of docs/model.md §4 is
``tau = ∂(V_g + Σ V_s)/∂q``; the tests compare the library's residual torque with a
finite-difference derivative of the potential computed here:

- ``V_g`` from ``pin.computePotentialEnergy`` (uses the model's gravity);
- each spring end at ``x = oMf[frame].act(p)`` after ``pin.framesForwardKinematics``;
- the spring laws of docs/model.md §3: extension ``V = F0 (L - l0) + k (L - l0)^2 / 2``,
  zero-free-length ``V = k L^2 / 2``, compression/gas ``V = F0 (l0 - L) + k (l0 - L)^2 / 2``,
  constant force ``V = F0 L``;
- a spring's own mass ``m`` as two point masses ``m/2`` at its ends (docs/model.md §5):
  ``V = -(m/2) g·(x_a + x_b)``;
- torsional springs on a joint ``i`` (docs/model.md §3.6): ``V = k (q_i - q0)^2 / 2 + τ0 (q_i - q0)``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin


@dataclasses.dataclass(frozen=True)
class RefSpring:
    """A spring as plain numbers: bodies, body-frame points [m] and its law."""

    body_a: str
    point_a: tuple
    body_b: str
    point_b: tuple
    stiffness: float
    free_length: float = 0.0
    initial_tension: float = 0.0  # F0 of the law: initial tension, preload or constant force [N]
    zero_free_length: bool = False
    law: str = "extension"  # "extension", "compression" (and gas) or "constant_force"
    mass: float = 0.0  # the spring's own mass [kg], half at each end

    def potential(self, length: float) -> float:
        """Stored energy [J] at length ``length`` [m]."""
        if self.zero_free_length:
            return 0.5 * self.stiffness * length**2
        if self.law == "constant_force":
            return self.initial_tension * length
        if self.law == "compression":
            compression = self.free_length - length
            return self.initial_tension * compression + 0.5 * self.stiffness * compression**2
        stretch = length - self.free_length
        return self.initial_tension * stretch + 0.5 * self.stiffness * stretch**2


@dataclasses.dataclass(frozen=True)
class RefTorsional:
    """A torsional spring as plain numbers: joint name, rate [N·m/rad], neutral angle [rad], preload [N·m]."""

    joint: str
    stiffness: float
    neutral_angle: float
    preload: float = 0.0

    def potential(self, angle: float) -> float:
        deflection = angle - self.neutral_angle
        return 0.5 * self.stiffness * deflection**2 + self.preload * deflection


class ReferencePotential:
    """``V(q) = V_g(q) + Σ V_s(L_s(q))`` [J] for a Pinocchio model and plain springs."""

    def __init__(self, model: pin.Model, springs: list[RefSpring], torsional: list[RefTorsional] = ()):
        self.model = model
        self.data = model.createData()
        self.springs = list(springs)
        self.torsional = list(torsional)
        self.has_mimic = any("Mimic" in joint.shortname() for joint in model.joints)
        self.frames = {}
        for spring in self.springs:
            for body in (spring.body_a, spring.body_b):
                if not model.existFrame(body):
                    raise KeyError(body)
                self.frames[body] = model.getFrameId(body)

    def anchor_positions(self, q: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
        pin.framesForwardKinematics(self.model, self.data, q)
        ends = []
        for spring in self.springs:
            xa = self.data.oMf[self.frames[spring.body_a]].act(np.asarray(spring.point_a, dtype=float))
            xb = self.data.oMf[self.frames[spring.body_b]].act(np.asarray(spring.point_b, dtype=float))
            ends.append((np.array(xa), np.array(xb)))
        return ends

    def lengths(self, q: np.ndarray) -> np.ndarray:
        return np.array([np.linalg.norm(xb - xa) for xa, xb in self.anchor_positions(q)])

    def gravity_potential(self, q: np.ndarray) -> float:
        """``V_g`` [J]: Pinocchio's ``computePotentialEnergy``; for models with mimic joints
        (which that algorithm rejects) the same sum written out, ``-Σ m_i g·c_i``."""
        if not self.has_mimic:
            return float(pin.computePotentialEnergy(self.model, self.data, q))
        pin.forwardKinematics(self.model, self.data, q)
        gravity = np.asarray(self.model.gravity.linear)
        return float(
            -sum(
                inertia.mass * gravity @ self.data.oMi[i].act(inertia.lever)
                for i, inertia in enumerate(self.model.inertias)
            )
        )

    def joint_angle(self, q: np.ndarray, joint: str) -> float:
        """Angle [rad] of a revolute (one coordinate) or continuous ((cos, sin) coordinates) joint."""
        model_joint = self.model.joints[self.model.getJointId(joint)]
        if model_joint.nq == 2:
            return float(np.arctan2(q[model_joint.idx_q + 1], q[model_joint.idx_q]))
        return float(q[model_joint.idx_q])

    def __call__(self, q: np.ndarray) -> float:
        gravity = self.gravity_potential(q)
        ends = self.anchor_positions(q)
        springs = sum(s.potential(float(np.linalg.norm(xb - xa))) for s, (xa, xb) in zip(self.springs, ends))
        g = np.asarray(self.model.gravity.linear)
        masses = sum(-0.5 * s.mass * float(g @ (xa + xb)) for s, (xa, xb) in zip(self.springs, ends))
        torsional = sum(t.potential(self.joint_angle(q, t.joint)) for t in self.torsional)
        return float(gravity + springs + masses + torsional)

    def torque(self, q: np.ndarray, step: float = 1e-4) -> np.ndarray:
        """``∂V/∂q`` by the fourth-order central difference along each velocity direction.

        ``pin.integrate`` moves along the joint coordinate (also for continuous joints,
        whose configuration is (cos, sin)). Truncation error ~ step^4, rounding ~ eps V / step.
        """
        nv = self.model.nv
        tau = np.empty(nv)
        for j in range(nv):

            def shifted(h, j=j):
                dv = np.zeros(nv)
                dv[j] = h
                return self(pin.integrate(self.model, q, dv))

            tau[j] = (-shifted(2 * step) + 8 * shifted(step) - 8 * shifted(-step) + shifted(-2 * step)) / (12 * step)
        return tau
