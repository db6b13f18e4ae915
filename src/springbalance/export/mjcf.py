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
- a spring's own mass as two point masses (bodies without a joint) at its ends on moving bodies;
- a pseudo-base's mimic chain (:mod:`springbalance.model.pseudo_bases`) as hinge joints tied to their primary
  joints by joint equality constraints, like every URDF mimic joint; its massless links get
  :data:`CHAIN_MASS` each, because MuJoCo refuses a massless moving body (a change of static torque below
  1e-11 N·m per metre of lever).

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
    law_warnings,
    number,
    resolve_package,
    source_urdf,
    vector,
)
from springbalance.export.mjcf_springs import SpringElements
from springbalance.files import write_text_atomic
from springbalance.model import robots
from springbalance.model.pseudo_bases import is_chain_link

if TYPE_CHECKING:  # lxml and yourdfpy (no stubs) are imported when a model is exported
    from lxml.etree import _Element
    from yourdfpy import Collision, Joint, Link, Mesh, Visual

__all__ = ["MUJOCO_MESH_FORMATS", "export_mjcf", "mjcf_string"]

#: mass [kg] (and principal moments [kg·m²]) of a pseudo-base chain link in MuJoCo, which refuses massless moving
#: bodies: at 1 m from a joint it weighs 1e-11 N·m
CHAIN_MASS = 1e-12
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
        builder.warnings.append(
            f"MuJoCo rejects an URDF inertia ({message}); balanceinertia is on, which changes "
            "rotational inertias (static torques are unaffected)"
        )
        xml = etree.tostring(builder.root, pretty_print=True, encoding="unicode")
        try:
            mujoco.MjSpec.from_string(xml).compile()
        except ValueError as error:
            raise InputError(f"MuJoCo rejects the exported model: {' '.join(str(error).split())}") from None
    return xml, law_warnings(design) + builder.warnings


class _MjcfBuilder(SpringElements):
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
        self.compiler = E(
            root,
            "compiler",
            angle="radian",
            inertiafromgeom="false",
            balanceinertia="false",
            fusestatic="false",
            discardvisual="false",
            boundmass="0",
            boundinertia="0",
            autolimits="true",
        )
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
    def _add_body(
        self,
        parent: _Element,
        link: Link,
        joint: Joint | None,
        links: dict[str, Link],
        children: dict[str, list[Joint]],
    ) -> None:
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
        if joint is not None and joint.type != "fixed" and is_chain_link(link.name, self.mechanism.pseudo_bases):
            # MuJoCo refuses a massless moving body: a pseudo-base chain link gets a speck (module docstring)
            E(body, "inertial", pos="0 0 0", mass=number(CHAIN_MASS), diaginertia=vector([CHAIN_MASS] * 3))
        elif not merged and inertial is not None and inertial.mass is not None and inertial.mass > 0:
            origin = inertial.origin if inertial.origin is not None else np.eye(4)
            rotation = origin[:3, :3]
            inertia = rotation @ (inertial.inertia if inertial.inertia is not None else np.zeros((3, 3))) @ rotation.T
            E(
                body,
                "inertial",
                pos=vector(origin[:3, 3]),
                mass=number(inertial.mass),
                fullinertia=vector(
                    [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2], inertia[1, 2]]
                ),
            )
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
            raise InputError(
                f"joint {joint.name!r} is {joint.type}; the MuJoCo export supports revolute, "
                "continuous, prismatic and fixed joints"
            )
        axis = joint.axis if joint.axis is not None else np.array([1.0, 0.0, 0.0])
        attributes = {"name": joint.name, "type": kinds[joint.type], "axis": vector(axis)}
        limit = joint.limit
        if (
            joint.type != "continuous"
            and limit is not None
            and limit.lower is not None
            and limit.upper is not None
            and limit.lower < limit.upper
        ):
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
            resolved = Path(filename[len("file://") :])
        else:
            resolved = Path(filename) if os.path.isabs(filename) or self.folder is None else self.folder / filename
        if resolved is None or not Path(resolved).is_file():
            self.warnings.append(f"mesh {filename!r} not found; geom {name!r} left out of the MuJoCo model")
            return None
        if Path(resolved).suffix.lower() not in MUJOCO_MESH_FORMATS:
            self.warnings.append(
                f"mesh {filename!r}: MuJoCo does not load {Path(resolved).suffix} files; "
                f"geom {name!r} left out of the MuJoCo model"
            )
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
    def _add_mimic(self, root: _Element) -> None:
        from lxml import etree

        mimics = [joint for joint in self.urdf.robot.joints if joint.mimic is not None]
        if not mimics:
            return
        equality = etree.SubElement(root, "equality")
        for joint in mimics:
            multiplier = joint.mimic.multiplier if joint.mimic.multiplier is not None else 1.0
            offset = joint.mimic.offset if joint.mimic.offset is not None else 0.0
            etree.SubElement(
                equality,
                "joint",
                joint1=joint.name,
                joint2=joint.mimic.joint,
                polycoef=vector([offset, multiplier, 0, 0, 0]),
            )
            self.warnings.append(
                f"mimic joint {joint.name!r} follows {joint.mimic.joint!r} through a joint equality constraint in "
                f"MuJoCo, which has a DOF for each: the holding torque of {joint.mimic.joint!r} is MuJoCo's torque on "
                f"it plus {multiplier:g} × the torque on {joint.name!r}"
            )


def _quaternion(rotation: npt.ArrayLike) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix."""
    import pinocchio as pin

    quaternion = pin.Quaternion(np.asarray(rotation, dtype=float))
    quaternion.normalize()
    return np.array([quaternion.w, quaternion.x, quaternion.y, quaternion.z])
