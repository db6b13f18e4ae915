r"""Export a balanced arm as a MuJoCo model (MJCF): tendon springs, actuators, joint springs.

``export_mjcf(design, "balanced.xml")`` writes a MuJoCo model built from the same URDF: one
body per URDF link (fixed joints become bodies without a joint, no fusing), the URDF inertials
exactly (``inertiafromgeom="false"``, ``balanceinertia="false"``), the design's gravity, and

- a site at every anchor and one spatial tendon per two-point spring (a nonlinear law, such as a
  force–length table, becomes its least-squares line over the workspace, with a warning). MuJoCo's tendon spring
  acts on the tendon length with the force :math:`-k (L - L_s)` (``stiffness`` k,
  ``springlength`` L_s; positive lengthens), i.e. the tension :math:`F = k (L - L_s)`. The
  laws of docs/model.md §3 map onto it with

  ========================  =========================================
  extension                 :math:`L_s = l_0 - F_0 / k`
  zero-free-length          :math:`L_s = 0`
  compression, gas          :math:`L_s = l_0 + F_0 / k`
  ========================  =========================================

  (``springlength="-1"`` means "length at qpos0" to MuJoCo: a law that lands exactly there, and
  every law with ``k = 0``, becomes a zero-free-length tendon spring plus a constant force);
- a constant tension ``F0`` (constant-force element, or the constant part above) as a
  ``general`` actuator on the tendon whose force does not depend on its control: gain 0 and
  the affine bias ``biasprm[0] = -F0`` (actuator force is positive when it lengthens);
- a torsional spring as joint ``stiffness`` k with ``springref`` :math:`q_0 - \tau_0 / k`
  (MuJoCo's joint spring torque is :math:`-k (q - q_{ref})`; several springs on one joint are
  summed), or a constant joint actuator when ``k = 0``;
- a spring's own mass as two point masses (bodies without a joint) at its ends on moving bodies.

MuJoCo's tendon spring is linear and two-sided, exactly like the laws springbalance evaluates;
a real spring may behave differently outside its range (an extension spring goes slack, a
gas spring hits its end stop). Such springs are reported in the returned warnings, never
changed. The model is written with full-precision numbers (MuJoCo's own writer, ``MjSpec.to_xml``,
prints 6 significant digits) and loaded back through ``mujoco.MjSpec`` and compiled before it is
saved. With zero velocity and acceleration, ``mj_inverse``'s ``qfrc_inverse`` minus the
actuators' ``qfrc_actuator`` is the holding torque ``design.residual_torque(q)`` [N·m].
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.errors import InputError
from springbalance.export.common import (
    GROUND,
    ExportReport,
    anchor_link_name,
    law_warnings,
    number,
    resolve_package,
    source_urdf,
    spring_name,
    vector,
)
from springbalance.files import write_text_atomic
from springbalance.model import robots
from springbalance.springs.laws.spring import Spring
from springbalance.springs.laws.two_point import TwoPointSpring

if TYPE_CHECKING:   # lxml and yourdfpy (no stubs) are imported when a model is exported
    from lxml.etree import _Element
    from yourdfpy import Collision, Joint, Link, Mesh, Visual

__all__ = ["MUJOCO_MESH_FORMATS", "export_mjcf", "mjcf_string"]

#: mesh formats MuJoCo loads
MUJOCO_MESH_FORMATS = (".stl", ".obj", ".msh")


def export_mjcf(design: EvaluatedDesign, path: str | Path) -> ExportReport:
    """Write the balanced arm as a MuJoCo model (MJCF); see the module docstring."""
    xml, warnings = mjcf_string(design)
    return ExportReport(Path(path), [write_text_atomic(path, xml)], warnings)


def mjcf_string(design: EvaluatedDesign) -> tuple[str, list[str]]:
    """(MJCF text, warnings) of the balanced arm; the text compiles with ``mujoco.MjSpec``."""
    import mujoco
    from lxml import etree

    text, folder = source_urdf(design.problem.mechanism)
    builder = _MjcfBuilder(design, text, folder)
    xml = etree.tostring(builder.build(), pretty_print=True, encoding="unicode")
    try:
        mujoco.MjSpec.from_string(xml).compile()
    except ValueError as error:
        message = " ".join(str(error).split())
        if "inertia must satisfy" not in message:
            raise InputError(f"MuJoCo rejects the exported model: {message}") from None
        builder.compiler.set("balanceinertia", "true")
        builder.warnings.append(f"MuJoCo rejects an URDF inertia ({message}); balanceinertia is on, which changes "
                                "rotational inertias (static torques are unaffected)")
        xml = etree.tostring(builder.root, pretty_print=True, encoding="unicode")
        try:
            mujoco.MjSpec.from_string(xml).compile()
        except ValueError as error:
            raise InputError(f"MuJoCo rejects the exported model: {' '.join(str(error).split())}") from None
    return xml, law_warnings(design) + builder.warnings


class _MjcfBuilder:
    """Builds the MJCF tree of the balanced arm from the design's URDF and values."""

    def __init__(self, design: EvaluatedDesign, urdf_text: str, folder: Path | None) -> None:
        import io

        import yourdfpy

        self.design = design
        self.mechanism = design.problem.mechanism
        self.folder = folder
        self.urdf = yourdfpy.URDF.load(io.BytesIO(urdf_text.encode()), build_scene_graph=False, load_meshes=False)
        self.warnings: list[str] = []
        self.meshes: dict[tuple[str, tuple[float, ...]], str] = {}
        self.joint_springs: dict[str, list] = {}

    def build(self) -> _Element:
        from lxml import etree

        E = etree.SubElement
        robot = self.urdf.robot
        self.root = root = etree.Element("mujoco", model=robot.name or "springbalance")
        self.compiler = E(root, "compiler", angle="radian", inertiafromgeom="false", balanceinertia="false",
                          fusestatic="false", discardvisual="false", boundmass="0", boundinertia="0",
                          autolimits="true")
        E(root, "option", gravity=vector(self.mechanism.gravity))
        self.asset = E(root, "asset")
        world = E(root, "worldbody")
        self.bodies = {GROUND: world}
        children: dict[str, list] = {}
        for joint in robot.joints:
            children.setdefault(joint.parent, []).append(joint)
        links = {link.name: link for link in robot.links}
        roots = [name for name in links if name not in {joint.child for joint in robot.joints}]
        if len(roots) != 1:
            raise InputError(f"the URDF has {len(roots)} root links ({', '.join(roots)}); expected one")
        root_link = roots[0]
        self._add_body(world, links[root_link], None, links, children)
        self._add_springs(root)
        self._add_mimic(root)
        if not len(self.asset):
            root.remove(self.asset)
        return root

    # ---------------------------------------------------------------- bodies
    def _add_body(self, parent: _Element, link: Link, joint: Joint | None, links: dict[str, Link],
                  children: dict[str, list[Joint]]) -> None:
        from lxml import etree

        E = etree.SubElement
        attributes = {"name": link.name}
        if joint is not None and joint.origin is not None:
            attributes["pos"] = vector(joint.origin[:3, 3])
            attributes["quat"] = vector(_quaternion(joint.origin[:3, :3]))
        # a root link called "world" is MuJoCo's world body (the name is taken); its mass holds nothing up
        merged = joint is None and link.name == "world"
        body = parent if merged else E(parent, "body", **attributes)
        self.bodies[link.name] = body
        inertial = link.inertial
        if not merged and inertial is not None and inertial.mass is not None and inertial.mass > 0:
            origin = inertial.origin if inertial.origin is not None else np.eye(4)
            rotation = origin[:3, :3]
            inertia = rotation @ (inertial.inertia if inertial.inertia is not None else np.zeros((3, 3))) @ rotation.T
            E(body, "inertial", pos=vector(origin[:3, 3]), mass=number(inertial.mass),
              fullinertia=vector([inertia[0, 0], inertia[1, 1], inertia[2, 2],
                                   inertia[0, 1], inertia[0, 2], inertia[1, 2]]))
        if joint is not None and joint.type != "fixed":
            self._add_joint(body, joint)
        for index, visual in enumerate(link.visuals):
            self._add_geom(body, visual, f"{link.name}_visual{index}", visual=True)
        for index, collision in enumerate(link.collisions):
            self._add_geom(body, collision, f"{link.name}_collision{index}", visual=False)
        for child in children.get(link.name, []):
            self._add_body(body, links[child.child], child, links, children)

    def _add_joint(self, body: _Element, joint: Joint) -> None:
        from lxml import etree

        kinds = {"revolute": "hinge", "continuous": "hinge", "prismatic": "slide"}
        if joint.type not in kinds:
            raise InputError(f"joint {joint.name!r} is {joint.type}; the MuJoCo export supports revolute, "
                             "continuous, prismatic and fixed joints")
        axis = joint.axis if joint.axis is not None else np.array([1.0, 0.0, 0.0])
        attributes = {"name": joint.name, "type": kinds[joint.type], "axis": vector(axis)}
        limit = joint.limit
        if joint.type != "continuous" and limit is not None and limit.lower is not None and limit.upper is not None \
                and limit.lower < limit.upper:
            attributes["range"] = vector([limit.lower, limit.upper])
            attributes["limited"] = "true"
        else:
            attributes["limited"] = "false"
        if joint.dynamics is not None:
            if joint.dynamics.damping:
                attributes["damping"] = number(joint.dynamics.damping)
            if joint.dynamics.friction:
                attributes["frictionloss"] = number(joint.dynamics.friction)
        etree.SubElement(body, "joint", **attributes)

    def _add_geom(self, body: _Element, element: Visual | Collision, name: str, visual: bool) -> None:
        from lxml import etree

        geometry = element.geometry
        attributes = {"name": name}
        if visual:
            attributes.update(contype="0", conaffinity="0", group="1")
        else:
            attributes.update(group="3")
        origin = element.origin if element.origin is not None else np.eye(4)
        attributes["pos"] = vector(origin[:3, 3])
        attributes["quat"] = vector(_quaternion(origin[:3, :3]))
        if geometry.box is not None:
            attributes.update(type="box", size=vector(np.asarray(geometry.box.size) / 2))
        elif geometry.cylinder is not None:
            attributes.update(type="cylinder", size=vector([geometry.cylinder.radius, geometry.cylinder.length / 2]))
        elif geometry.sphere is not None:
            attributes.update(type="sphere", size=number(geometry.sphere.radius))
        elif geometry.mesh is not None:
            mesh = self._mesh_asset(geometry.mesh, name)
            if mesh is None:
                return
            attributes.update(type="mesh", mesh=mesh)
        else:
            return
        etree.SubElement(body, "geom", **attributes)

    def _mesh_asset(self, mesh: Mesh, name: str) -> str | None:
        from lxml import etree

        filename = mesh.filename
        if filename.startswith("package://"):
            resolved = resolve_package(filename, robots.package_directories())
        elif filename.startswith("file://"):
            resolved = Path(filename[len("file://"):])
        else:
            resolved = Path(filename) if os.path.isabs(filename) or self.folder is None else self.folder / filename
        if resolved is None or not Path(resolved).is_file():
            self.warnings.append(f"mesh {filename!r} not found; geom {name!r} left out of the MuJoCo model")
            return None
        if Path(resolved).suffix.lower() not in MUJOCO_MESH_FORMATS:
            self.warnings.append(f"mesh {filename!r}: MuJoCo does not load {Path(resolved).suffix} files; "
                                 f"geom {name!r} left out of the MuJoCo model")
            return None
        key = str(Path(resolved).resolve())
        scale = mesh.scale
        scale = np.ones(3) if scale is None else np.broadcast_to(np.asarray(scale, dtype=float), (3,))
        key_scale = (key, tuple(scale))
        if key_scale not in self.meshes:
            asset = f"mesh{len(self.meshes)}_{Path(key).stem}"
            attributes = {"name": asset, "file": key}
            if not np.all(scale == 1):
                attributes["scale"] = vector(scale)
            etree.SubElement(self.asset, "mesh", **attributes)
            self.meshes[key_scale] = asset
        return self.meshes[key_scale]

    # ---------------------------------------------------------------- springs
    def _add_springs(self, root: _Element) -> None:
        from lxml import etree

        E = etree.SubElement
        tendon = E(root, "tendon")
        actuator = E(root, "actuator")
        for spring, record in zip(self.design.problem.springs, self.design.springs):
            if not spring.anchors:
                self._add_torsional(actuator, spring, record)
                continue
            sites = []   # the tendon's path through the sites; a pulley's cylinder is drawn, not wrapped
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
                    f"lengths, off the law by up to {deviation:.3g} N")
            attributes = {"name": spring.name, "stiffness": number(stiffness), "width": "0.004",
                          "rgba": "0.9 0.6 0.1 1"}
            if stiffness > 0:
                attributes["springlength"] = vector([spring_length, spring_length])
            spatial = E(tendon, "spatial", **attributes)
            for site in sites:
                E(spatial, "site", site=site)
            if constant != 0:
                # constant tension F0 pulls: the actuator force (positive lengthens) is -F0, whatever the control
                E(actuator, "general", name=f"{spring.name}_constant_force", tendon=spring.name, gainprm="0",
                  biastype="affine", biasprm=vector([-constant, 0, 0]))
            mass = record.get("mass")
            if mass:
                for end in getattr(spring, "spring_ends", spring.anchors):
                    body_name = record[end]["body"]
                    if self.mechanism.is_ground(body_name):
                        continue
                    point_mass = E(self._body(body_name), "body", name=f"{spring.name}_mass_{end}",
                                   pos=vector(record[end]["point"]))
                    E(point_mass, "inertial", pos="0 0 0", mass=number(0.5 * mass), diaginertia="0 0 0")
        self._finish_torsional(actuator)
        for element in (tendon, actuator):
            if not len(element):
                root.remove(element)

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
            neighbours.append(rotation.T @ (point - translation) - centre)       # in the pulley's body frame
        axis = np.cross(neighbours[0], neighbours[1])
        for fallback in ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]):
            if np.linalg.norm(axis) >= 1e-9:
                break
            axis = np.cross(neighbours[0], fallback)
        etree.SubElement(body, "geom", name=f"{anchor_link_name(spring_name(spring), end)}_pulley", type="cylinder",
                         pos=vector(centre), zaxis=vector(axis / np.linalg.norm(axis)),
                         size=vector([radius, 0.005]), contype="0", conaffinity="0", mass="0",
                         rgba="0.3 0.3 0.3 1")

    def _pulley_warning(self, spring: Spring, record: dict) -> str:
        """How far MuJoCo's tendon (through the pulleys' centres) is from the wrapped cable over the workspace."""
        problem = self.design.problem
        kinematics = problem.base_workspace.kinematics()
        points = []   # world positions (N×3) [m] of the path's points
        for end in spring.anchors:
            body, local = record[end]["body"], np.asarray(record[end]["point"], dtype=float)
            if self.mechanism.is_ground(body):
                rotation, translation = self._reference_placement(body)
                points.append(np.broadcast_to(rotation @ local + translation, (problem.base_workspace.size, 3)))
            else:
                points.append(kinematics.body(body).points(local))
        centres = sum(np.linalg.norm(second - first, axis=1) for first, second in zip(points, points[1:]))   # [m]
        column = problem.springs.index(spring)
        wrapped = self.design.evaluation.lengths[:problem.base_workspace.size, column] + float(record["cable_length"])
        error = float(np.max(np.abs(wrapped - centres)))
        return (f"spring {spring.name!r}: MuJoCo's spatial tendon runs through the centres of its wrapping pulleys "
                f"(a MuJoCo wrapping geom only deflects a tendon that would cut through it, and a pulley sits inside the "
                f"cable's bend), so its length is off the wrapped cable's by up to {error:.3g} m over the workspace; "
                f"the pulleys are drawn as cylinders")

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
        total[0] += stiffness                                  # Σ k [N·m/rad]
        total[1] += stiffness * neutral - preload              # Σ (k q0 - τ0) [N·m]
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
                etree.SubElement(actuator, "general", name=f"{'_'.join(names)}_constant_torque", joint=joint_name,
                                 gainprm="0", biastype="affine", biasprm=vector([offset, 0, 0]))

    def _add_mimic(self, root: _Element) -> None:
        from lxml import etree

        mimics = [joint for joint in self.urdf.robot.joints if joint.mimic is not None]
        if not mimics:
            return
        equality = etree.SubElement(root, "equality")
        for joint in mimics:
            multiplier = joint.mimic.multiplier if joint.mimic.multiplier is not None else 1.0
            offset = joint.mimic.offset if joint.mimic.offset is not None else 0.0
            etree.SubElement(equality, "joint", joint1=joint.name, joint2=joint.mimic.joint,
                             polycoef=vector([offset, multiplier, 0, 0, 0]))
            self.warnings.append(
                f"mimic joint {joint.name!r} follows {joint.mimic.joint!r} through a joint equality constraint in "
                f"MuJoCo, which has a DOF for each: the holding torque of {joint.mimic.joint!r} is MuJoCo's torque on "
                f"it plus {multiplier:g} × the torque on {joint.name!r}")

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
    k, constant, deviation = spring.tendon_law(record, lengths)          # F = k L + constant
    if getattr(spring, "routed", False):
        # MuJoCo's tendon is the whole path, ℓ = L + cable: F = k ℓ + (constant − k cable)
        constant -= k * float(record["cable_length"])
    if k <= 0:
        return 0.0, 0.0, constant, deviation
    length = -constant / k                         # L_s with F = k (L - L_s)
    if length == -1.0:                             # MuJoCo's "length at qpos0" sentinel
        return k, 0.0, constant, deviation
    return k, length, 0.0, deviation


def _quaternion(rotation: npt.ArrayLike) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix."""
    import pinocchio as pin

    quaternion = pin.Quaternion(np.asarray(rotation, dtype=float))
    quaternion.normalize()
    return np.array([quaternion.w, quaternion.x, quaternion.y, quaternion.z])
