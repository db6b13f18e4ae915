"""Independent physics for the tests: total potential energy from Pinocchio alone.

Nothing here imports springbalance's torque model. The holding torque of MODEL.md §3 is
``tau = ∂(V_g + Σ V_s)/∂q``; the tests compare the library's residual torque with a
finite-difference derivative of the potential computed here:

- ``V_g`` from ``pin.computePotentialEnergy`` (uses the model's gravity);
- each spring end at ``x = oMf[frame].act(p)`` after ``pin.framesForwardKinematics``;
- the spring laws of MODEL.md §2: extension ``V = F0 (L - l0) + k (L - l0)^2 / 2``,
  zero-free-length ``V = k L^2 / 2``.
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
    initial_tension: float = 0.0
    zero_free_length: bool = False

    def potential(self, length: float) -> float:
        """Stored energy [J] at length ``length`` [m]."""
        if self.zero_free_length:
            return 0.5 * self.stiffness * length**2
        stretch = length - self.free_length
        return self.initial_tension * stretch + 0.5 * self.stiffness * stretch**2


class ReferencePotential:
    """``V(q) = V_g(q) + Σ V_s(L_s(q))`` [J] for a Pinocchio model and plain springs."""

    def __init__(self, model: pin.Model, springs: list[RefSpring]):
        self.model = model
        self.data = model.createData()
        self.springs = list(springs)
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
        return float(-sum(inertia.mass * gravity @ self.data.oMi[i].act(inertia.lever)
                          for i, inertia in enumerate(self.model.inertias)))

    def __call__(self, q: np.ndarray) -> float:
        gravity = self.gravity_potential(q)
        springs = sum(s.potential(L) for s, L in zip(self.springs, self.lengths(q)))
        return float(gravity + springs)

    def torque(self, q: np.ndarray, step: float = 1e-4) -> np.ndarray:
        """``∂V/∂q`` by the fourth-order central difference along each velocity direction.

        ``pin.integrate`` moves along the joint coordinate (also for continuous joints,
        whose configuration is (cos, sin)). Truncation error ~ step^4, rounding ~ eps V / step.
        """
        nv = self.model.nv
        tau = np.empty(nv)
        for j in range(nv):
            def shifted(h):
                dv = np.zeros(nv)
                dv[j] = h
                return self(pin.integrate(self.model, q, dv))
            tau[j] = (-shifted(2 * step) + 8 * shifted(step) - 8 * shifted(-step) + shifted(-2 * step)) / (12 * step)
        return tau
