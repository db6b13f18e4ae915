"""The springs of the MuJoCo export: a site at every anchor, a spatial tendon per two-point spring (its law as
MuJoCo's linear tendon spring plus a constant-force actuator), pulleys as sites the tendon wraps, torsional
springs as joint stiffness, forces along a fixed direction as site actuators
(:mod:`springbalance.export.mjcf_directed`), and a spring's own mass as point masses (see :mod:`springbalance.export.mjcf`,
whose builder these methods are part of).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.errors import InputError
from springbalance.export.common import GROUND, anchor_link_name, number, spring_name, vector
from springbalance.export.mjcf_directed import add_directed
from springbalance.model.mechanism import Mechanism
from springbalance.springs.laws.directed import DirectedSpring
from springbalance.springs.laws.spring import Spring
from springbalance.springs.laws.two_point import TwoPointSpring

if TYPE_CHECKING:  # lxml (no stubs) is imported when a model is exported
    from lxml.etree import _Element


class SpringElements:
    """The spring part of the MJCF builder (a base of ``_MjcfBuilder``, which sets the attributes below)."""

    design: EvaluatedDesign
    mechanism: Mechanism
    warnings: list[str]
    joint_springs: dict[str, list]
    bodies: dict[str, _Element]
    root: _Element

    def _add_springs(self, root: _Element) -> None:
        from lxml import etree

        E = etree.SubElement
        tendon = E(root, "tendon")
        actuator = E(root, "actuator")
        for spring, record in zip(self.design.problem.springs, self.design.springs):
            if not spring.anchors:
                self._add_torsional(actuator, spring, record)
                continue
            if isinstance(spring, DirectedSpring):  # a force along a fixed direction: a site actuator
                add_directed(self._body, actuator, spring, record)
                continue
            sites = []  # the tendon's path through the sites; a pulley's cylinder is drawn, not wrapped
            for end, radius in zip(spring.anchors, getattr(spring, "radii", [0.0] * len(spring.anchors))):
                body = self._body(record[end]["body"])
                name = anchor_link_name(spring_name(spring), end)
                E(body, "site", name=name, pos=vector(record[end]["point"]), size="0.01")
                sites.append(name)
                if radius > 0:
                    self._add_pulley(body, spring, end, record, radius)
            if any(radius > 0 for radius in getattr(spring, "radii", ())):
                self.warnings.append(self._pulley_warning(spring, record))
            lengths = self.design.evaluation.lengths[:, self.design.problem.springs.index(spring)]
            stiffness, spring_length, constant, deviation = _tendon_law(spring, record, lengths)  # [N/m], [m], [N], [N]
            if deviation > 0:
                self.warnings.append(
                    f"spring {spring.name!r} ({spring.kind}) is nonlinear: its MuJoCo tendon is the least-squares line "
                    f"F = {stiffness:.6g} N/m · (L − {spring_length:.6g} m) + {constant:.6g} N over the workspace "
                    f"lengths, off the law by up to {deviation:.3g} N"
                )
            attributes = {
                "name": spring.name,
                "stiffness": number(stiffness),
                "width": "0.004",
                "rgba": "0.9 0.6 0.1 1",
            }
            if stiffness > 0:
                attributes["springlength"] = vector([spring_length, spring_length])
            spatial = E(tendon, "spatial", **attributes)
            for site in sites:
                E(spatial, "site", site=site)
            if constant != 0:
                # constant tension F0 pulls: the actuator force (positive lengthens) is -F0, whatever the control
                E(
                    actuator,
                    "general",
                    name=f"{spring.name}_constant_force",
                    tendon=spring.name,
                    gainprm="0",
                    biastype="affine",
                    biasprm=vector([-constant, 0, 0]),
                )
            self._add_point_masses(spring, record)
        self._finish_torsional(actuator)
        for element in (tendon, actuator):
            if not len(element):
                root.remove(element)

    def _add_point_masses(self, spring: Spring, record: dict) -> None:
        """A spring's own mass [kg] as two point masses, half at each end on a moving body (none on the ground)."""
        from lxml import etree

        mass = record.get("mass")
        if not mass:
            return
        for end in getattr(spring, "spring_ends", spring.anchors):
            body_name = record[end]["body"]
            if self.mechanism.is_ground(body_name):
                continue
            point_mass = etree.SubElement(
                self._body(body_name), "body", name=f"{spring.name}_mass_{end}", pos=vector(record[end]["point"])
            )
            etree.SubElement(point_mass, "inertial", pos="0 0 0", mass=number(0.5 * mass), diaginertia="0 0 0")

    def _add_pulley(self, body: _Element, spring: Spring, end: str, record: dict, radius: float) -> None:
        """A cylinder of ``radius`` [m] drawn at the pulley ``end`` of a routed spring (no contact, no
        mass), its axis normal to the plane of the pulley and its neighbours at the reference pose."""
        from lxml import etree

        ends = list(spring.anchors)
        index = ends.index(end)
        centre = np.asarray(record[end]["point"], dtype=float)
        rotation, translation = self._reference_placement(record[end]["body"])
        neighbours = []
        for other in (ends[index - 1], ends[index + 1]):
            r_other, t_other = self._reference_placement(record[other]["body"])
            point = r_other @ np.asarray(record[other]["point"], dtype=float) + t_other
            neighbours.append(rotation.T @ (point - translation) - centre)  # in the pulley's body frame
        axis = np.cross(neighbours[0], neighbours[1])
        for fallback in ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]):
            if np.linalg.norm(axis) >= 1e-9:
                break
            axis = np.cross(neighbours[0], fallback)
        etree.SubElement(
            body,
            "geom",
            name=f"{anchor_link_name(spring_name(spring), end)}_pulley",
            type="cylinder",
            pos=vector(centre),
            zaxis=vector(axis / np.linalg.norm(axis)),
            size=vector([radius, 0.005]),
            contype="0",
            conaffinity="0",
            mass="0",
            rgba="0.3 0.3 0.3 1",
        )

    def _pulley_warning(self, spring: Spring, record: dict) -> str:
        """How far MuJoCo's tendon (through the pulleys' centres) is from the wrapped cable over the workspace."""
        problem = self.design.problem
        kinematics = problem.base_workspace.kinematics()
        points = []  # world positions (N×3) [m] of the path's points
        for end in spring.anchors:
            body, local = record[end]["body"], np.asarray(record[end]["point"], dtype=float)
            if self.mechanism.is_ground(body):
                rotation, translation = self._reference_placement(body)
                points.append(np.broadcast_to(rotation @ local + translation, (problem.base_workspace.size, 3)))
            else:
                points.append(kinematics.body(body).points(local))
        centres = sum(np.linalg.norm(second - first, axis=1) for first, second in zip(points, points[1:]))  # [m]
        column = problem.springs.index(spring)
        wrapped = self.design.evaluation.lengths[: problem.base_workspace.size, column] + float(record["cable_length"])
        error = float(np.max(np.abs(wrapped - centres)))
        return (
            f"spring {spring.name!r}: MuJoCo's spatial tendon runs through the centres of its wrapping pulleys "
            f"(a MuJoCo wrapping geom only deflects a tendon that would cut through it, and a pulley sits inside the "
            f"cable's bend), so its length is off the wrapped cable's by up to {error:.3g} m over the workspace; "
            f"the pulleys are drawn as cylinders"
        )

    def _reference_placement(self, body: str) -> tuple[np.ndarray, np.ndarray]:
        """World rotation and translation of ``body`` at the model's reference pose (all joints 0)."""
        import pinocchio as pin

        mechanism = self.design.problem.mechanism
        data = mechanism.model.createData()
        pin.framesForwardKinematics(mechanism.model, data, pin.neutral(mechanism.model))
        placement = data.oMf[mechanism.frame_id(body)]
        return np.array(placement.rotation), np.array(placement.translation)

    def _add_torsional(self, actuator: _Element, spring: Spring, record: dict) -> None:
        """Collect a torsional spring; :meth:`_finish_torsional` writes each joint's sum."""
        stiffness, neutral, preload = record["stiffness"], record["neutral_angle"], record.get("preload", 0.0)
        total = self.joint_springs.setdefault(record["joint"], [0.0, 0.0, []])
        total[0] += stiffness  # Σ k [N·m/rad]
        total[1] += stiffness * neutral - preload  # Σ (k q0 - τ0) [N·m]
        total[2].append(spring.name)

    def _finish_torsional(self, actuator: _Element) -> None:
        from lxml import etree

        for joint_name, (stiffness, offset, names) in self.joint_springs.items():
            joint = self.root.find(f".//body/joint[@name='{joint_name}']")
            # Σ k_i (q - q0_i) + τ0_i = k (q - q_ref) with k = Σ k_i, q_ref = Σ (k_i q0_i - τ0_i) / k;
            # MuJoCo's joint spring applies -k (q - springref)
            if stiffness > 0:
                joint.set("stiffness", number(stiffness))
                joint.set("springref", number(offset / stiffness))
            elif offset != 0:
                # constant torque τ0 = -offset held by the springs; the actuator applies -τ0 whatever its control
                etree.SubElement(
                    actuator,
                    "general",
                    name=f"{'_'.join(names)}_constant_torque",
                    joint=joint_name,
                    gainprm="0",
                    biastype="affine",
                    biasprm=vector([offset, 0, 0]),
                )

    def _body(self, name: str) -> _Element:
        if name == GROUND:
            return self.bodies[GROUND]
        return self.bodies[name]


def _tendon_law(spring: Spring, record: dict, lengths: np.ndarray) -> tuple[float, float, float, float]:
    """MuJoCo tendon ``(stiffness k [N/m], springlength L_s [m], constant tension F_c [N], deviation [N])``
    with ``F(L) = k (L - L_s) + F_c`` the spring's law (:meth:`~springbalance.springs.laws.base.TwoPointSpring.tendon_law`:
    exact for a linear law; a nonlinear one gives its best line over the workspace ``lengths`` [m]
    and the largest deviation there)."""
    if not isinstance(spring, TwoPointSpring):
        raise InputError(f"spring {spring.name!r} ({spring.kind}): a MuJoCo tendon is made of a two-point spring only")
    k, constant, deviation = spring.tendon_law(record, lengths)  # F = k L + constant
    if getattr(spring, "routed", False):
        # MuJoCo's tendon is the whole path, ℓ = L + cable: F = k ℓ + (constant − k cable)
        constant -= k * float(record["cable_length"])
    if k <= 0:
        return 0.0, 0.0, constant, deviation
    length = -constant / k  # L_s with F = k (L - L_s)
    if length == -1.0:  # MuJoCo's "length at qpos0" sentinel
        return k, 0.0, constant, deviation
    return k, length, 0.0, deviation
