"""The arm's geometry for Meshcat: the URDF's visual meshes, or a stick figure when there are none."""

from __future__ import annotations

import warnings

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from springbalance.model import robots
from springbalance.model.mechanism import Mechanism
from springbalance.model.native import quiet_native_stderr
from springbalance.viz.helix import spring_rotation

#: Colour of the stick figure drawn for a mechanism without visual geometry (RGBA).
STICK_COLOR = (0.2, 0.3, 0.8, 1.0)


def visual_geometry(mechanism: Mechanism) -> pin.GeometryModel | None:
    """Pinocchio visual ``GeometryModel`` of the mechanism's URDF, or None when there is none.

    ``package://`` paths resolve against the URDF's folder, its parents and the
    example-robot-data share folder.
    """
    source = mechanism.source
    directories = robots.mesh_directories(source)
    try:
        with quiet_native_stderr():
            if source.get("kind") in ("urdf", "robot"):
                return pin.buildGeomFromUrdf(
                    mechanism.model, source["path"], pin.GeometryType.VISUAL, package_dirs=directories
                )
            if source.get("kind") == "urdf_string":
                return pin.buildGeomFromUrdfString(
                    mechanism.model, source["text"], pin.GeometryType.VISUAL, package_dirs=directories
                )
    except (RuntimeError, ValueError, OSError) as error:
        warnings.warn(
            f"visual geometry of {mechanism.name!r} could not be loaded ({error}); drawing a stick figure", stacklevel=2
        )
    return None


def stick_figure(model: pin.Model) -> pin.GeometryModel:
    """Visual geometry for a model without any: a sphere at each joint, rods from each joint
    to its children, its body frames and its centre of mass."""
    import coal

    geometry = pin.GeometryModel()
    radius = 0.012  # [m]

    def add(name: str, joint: int, shape: coal.CollisionGeometry, pose: pin.SE3) -> None:
        obj = pin.GeometryObject(name, joint, pose, shape)
        obj.meshColor = np.array(STICK_COLOR)
        geometry.addGeometryObject(obj)

    def rod(name: str, joint: int, start: npt.ArrayLike, end: npt.ArrayLike) -> None:
        axis = np.asarray(end) - np.asarray(start)
        length = float(np.linalg.norm(axis))
        if length < 1e-6:
            return
        rotation = spring_rotation(axis, np.eye(3)[int(np.argmin(np.abs(axis)))])
        add(
            name,
            joint,
            coal.Cylinder(radius * 0.7, length),
            pin.SE3(rotation, (np.asarray(start) + np.asarray(end)) / 2),
        )

    for joint in range(1, model.njoints):
        add(f"joint_{model.names[joint]}", joint, coal.Sphere(radius * 1.5), pin.SE3.Identity())
        rod(f"link_{model.names[joint]}", model.parents[joint], np.zeros(3), model.jointPlacements[joint].translation)
        lever = model.inertias[joint].lever
        if model.inertias[joint].mass > 0:
            rod(f"com_rod_{model.names[joint]}", joint, np.zeros(3), lever)
            add(f"com_{model.names[joint]}", joint, coal.Sphere(radius * 1.2), pin.SE3(np.eye(3), lever))
    for index, frame in enumerate(model.frames):
        if frame.type == pin.FrameType.BODY and frame.parentJoint > 0:
            rod(f"frame_{index}_{frame.name}", frame.parentJoint, np.zeros(3), frame.placement.translation)
    return geometry
