"""The mechanism: an immutable Pinocchio model plus the names springbalance needs.

A :class:`Mechanism` is built from a URDF file, a URDF string, an example-robot-data robot
name or an existing ``pinocchio.Model``. It knows its *degrees of freedom* (the one-DOF
joints that the workspace samples: revolute, continuous and prismatic; mimic joints follow
their primary joint) and its *bodies* (the URDF links, plus ``universe`` for the ground),
which are where spring ends attach.

Units: joint coordinates in rad (revolute, continuous) or m (prismatic); gravity in m/s².
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import sys
import warnings
from pathlib import Path


import numpy as np
import pinocchio as pin

from springbalance.model import robots
from springbalance.errors import InputError

GROUND = "universe"

_REVOLUTE = {"JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned"}
_CONTINUOUS = {"JointModelRUBX", "JointModelRUBY", "JointModelRUBZ", "JointModelRevoluteUnboundedUnaligned"}
_PRISMATIC = {"JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned"}


@dataclasses.dataclass(frozen=True)
class Joint:
    """One degree of freedom of the mechanism.

    Attributes:
        name: URDF joint name.
        kind: ``"revolute"``, ``"continuous"`` or ``"prismatic"``.
        index_q: first index in Pinocchio's configuration vector (two slots, cos and sin,
            for a continuous joint).
        index_v: index in the velocity/torque vector.
        lower, upper: range from the URDF [rad or m]; ``[-pi, pi]`` for continuous joints.
    """

    name: str
    kind: str
    index_q: int
    index_v: int
    lower: float
    upper: float

    @property
    def unit(self) -> str:
        """Unit of the joint coordinate."""
        return "m" if self.kind == "prismatic" else "rad"

    @property
    def torque_unit(self) -> str:
        """Unit of the generalised force on this joint."""
        return "N" if self.kind == "prismatic" else "N·m"


class Mechanism:
    """A Pinocchio model with named degrees of freedom and bodies.

    Use the constructors :meth:`from_urdf`, :meth:`from_urdf_string`, :meth:`from_robot`
    or :meth:`from_model`.

    Attributes:
        model: the ``pinocchio.Model`` (gravity already set).
        joints: the degrees of freedom, in the order of the torque vector.
        source: how to rebuild this mechanism (saved with designs).
    """

    def __init__(self, model: pin.Model, source: dict | None = None, gravity=None):
        self.model = model.copy() if hasattr(model, "copy") else pin.Model(model)
        if gravity is not None:
            self.model.gravity.linear = _gravity_vector(gravity)
        self.source = dict(source or {"kind": "model"})
        self.source["gravity"] = [float(v) for v in self.model.gravity.linear]
        self.joints = _degrees_of_freedom(self.model)
        if len(self.joints) != self.model.nv:
            raise InputError(
                f"mechanism {self.name!r}: {self.model.nv} velocity DOFs but {len(self.joints)} one-DOF joints; "
                "only revolute, continuous, prismatic and mimic joints are supported"
            )
        self._frame_ids = {GROUND: 0}
        for frame_id, frame in enumerate(self.model.frames):
            if frame.type == pin.FrameType.BODY:
                self._frame_ids.setdefault(frame.name, frame_id)

    # ----------------------------------------------------------------- constructors
    @classmethod
    def from_urdf(cls, path: str | Path, gravity=None, mimic: bool = False) -> "Mechanism":
        """Load a URDF file. ``gravity``: magnitude g (then (0, 0, -g)) or a 3-vector [m/s²]."""
        path = Path(path)
        if not path.is_file():
            raise InputError(f"URDF file {str(path)!r} does not exist")
        try:
            with _quiet_native_stderr():
                model = pin.buildModelFromUrdf(str(path), mimic=mimic)
        except Exception as exc:  # Pinocchio raises RuntimeError/ValueError with C++ text
            raise InputError(f"URDF file {str(path)!r} could not be parsed: {_one_line(exc)}") from None
        if not mimic:
            _warn_unused_mimic(path.read_text(errors="replace"), str(path))
        source = {"kind": "urdf", "path": str(path.resolve()), "mimic": mimic}
        return cls(model, source=source, gravity=gravity)

    @classmethod
    def from_urdf_string(cls, text: str, gravity=None, mimic: bool = False) -> "Mechanism":
        """Parse a URDF given as XML text."""
        try:
            with _quiet_native_stderr():
                model = pin.buildModelFromXML(text, mimic=mimic)
        except Exception as exc:
            raise InputError(f"URDF string could not be parsed: {_one_line(exc)}") from None
        if not mimic:
            _warn_unused_mimic(text, "URDF string")
        return cls(model, source={"kind": "urdf_string", "text": text, "mimic": mimic}, gravity=gravity)

    @classmethod
    def from_robot(cls, name: str, gravity=None, mimic: bool = False) -> "Mechanism":
        """Load a robot of example-robot-data by name (``"ur5"``, ``"panda"``, ...)."""
        mechanism = cls.from_urdf(robots.robot_urdf(name), gravity=gravity, mimic=mimic)
        mechanism.source = {**mechanism.source, "kind": "robot", "robot": name}
        return mechanism

    @classmethod
    def from_model(cls, model: pin.Model, gravity=None) -> "Mechanism":
        """Wrap an existing Pinocchio model (it is copied)."""
        return cls(model, source={"kind": "model"}, gravity=gravity)

    @classmethod
    def from_source(cls, source: dict) -> "Mechanism":
        """Rebuild a mechanism from its :attr:`source` record (as saved in a design file)."""
        kind = source.get("kind")
        gravity = source.get("gravity")
        mimic = bool(source.get("mimic", False))
        if kind == "robot":
            return cls.from_robot(source["robot"], gravity=gravity, mimic=mimic)
        if kind == "urdf":
            return cls.from_urdf(source["path"], gravity=gravity, mimic=mimic)
        if kind == "urdf_string":
            return cls.from_urdf_string(source["text"], gravity=gravity, mimic=mimic)
        raise InputError(f"cannot rebuild a mechanism from source kind {kind!r} (a bare Pinocchio model is not saved)")

    # ----------------------------------------------------------------- names
    @property
    def name(self) -> str:
        return self.model.name

    @property
    def nv(self) -> int:
        return self.model.nv

    @property
    def joint_names(self) -> list[str]:
        return [joint.name for joint in self.joints]

    @property
    def body_names(self) -> list[str]:
        """Bodies that can carry a spring end: ``universe`` and every URDF link."""
        return list(self._frame_ids)

    @property
    def gravity(self) -> np.ndarray:
        """Gravity vector [m/s²]."""
        return np.array(self.model.gravity.linear)

    def joint(self, name: str) -> Joint:
        """The degree of freedom called ``name``."""
        for joint in self.joints:
            if joint.name == name:
                return joint
        raise InputError(f"unknown joint {name!r} in mechanism {self.name!r}; joints: {', '.join(self.joint_names)}")

    def frame_id(self, body: str) -> int:
        """Pinocchio frame index of the body (URDF link) ``body``."""
        try:
            return self._frame_ids[body]
        except KeyError:
            raise InputError(
                f"unknown body {body!r} in mechanism {self.name!r}; bodies: {', '.join(self.body_names)}"
            ) from None

    def is_ground(self, body: str) -> bool:
        """True when ``body`` cannot move (the universe or a link welded to it)."""
        return self.model.frames[self.frame_id(body)].parentJoint == 0

    # ----------------------------------------------------------------- coordinates
    def configurations(self, joint_values: np.ndarray) -> np.ndarray:
        """Pinocchio configurations ``q`` (N×nq) from joint coordinates (N×nv).

        Revolute and prismatic joints copy their coordinate; a continuous joint stores
        ``(cos θ, sin θ)``.
        """
        joint_values = np.atleast_2d(np.asarray(joint_values, dtype=float))
        if joint_values.shape[1] != self.nv:
            raise InputError(
                f"joint values have {joint_values.shape[1]} columns, mechanism {self.name!r} has {self.nv} "
                f"degrees of freedom ({', '.join(self.joint_names)})"
            )
        q = np.tile(pin.neutral(self.model), (joint_values.shape[0], 1))
        for column, joint in enumerate(self.joints):
            if joint.kind == "continuous":
                q[:, joint.index_q] = np.cos(joint_values[:, column])
                q[:, joint.index_q + 1] = np.sin(joint_values[:, column])
            else:
                q[:, joint.index_q] = joint_values[:, column]
        return q

    def __repr__(self) -> str:
        return f"Mechanism({self.name!r}, joints={self.joint_names})"


def _degrees_of_freedom(model: pin.Model) -> list[Joint]:
    joints = []
    for joint_id in range(1, model.njoints):
        joint_model = model.joints[joint_id]
        kind_name = joint_model.shortname()
        name = model.names[joint_id]
        if "Mimic" in kind_name or joint_model.nv == 0:
            continue
        if kind_name in _REVOLUTE:
            kind = "revolute"
        elif kind_name in _CONTINUOUS:
            kind = "continuous"
        elif kind_name in _PRISMATIC:
            kind = "prismatic"
        else:
            raise InputError(
                f"joint {name!r} is a {kind_name}; springbalance supports revolute, continuous and prismatic joints"
            )
        iq, iv = joint_model.idx_q, joint_model.idx_v
        if kind == "continuous":
            lower, upper = -np.pi, np.pi
        else:
            lower, upper = float(model.lowerPositionLimit[iq]), float(model.upperPositionLimit[iq])
            if not (np.isfinite(lower) and np.isfinite(upper)) or lower >= upper:
                lower, upper = (-np.pi, np.pi) if kind == "revolute" else (-1.0, 1.0)
        joints.append(Joint(name, kind, iq, iv, lower, upper))
    return sorted(joints, key=lambda joint: joint.index_v)


def _warn_unused_mimic(text: str, where: str) -> None:
    """Warn when a URDF declares mimic joints but is loaded with ``mimic=False`` (they become independent)."""
    import xml.etree.ElementTree as ElementTree

    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError:
        return
    names = [joint.get("name", "?") for joint in root.iter("joint") if joint.find("mimic") is not None]
    if names:
        warnings.warn(f"{where} declares mimic joints ({', '.join(names)}); they are loaded as independent joints. "
                      "Pass mimic=True (config: mechanism.mimic: true) to couple them to their primary joints.",
                      stacklevel=3)


def _gravity_vector(gravity) -> np.ndarray:
    try:
        vector = np.asarray(gravity, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"gravity must be a magnitude or a finite 3-vector, got {gravity!r}") from None
    if vector.ndim == 0:
        vector = np.array([0.0, 0.0, -float(vector)])
    if vector.shape != (3,) or not np.all(np.isfinite(vector)):
        raise InputError(f"gravity must be a magnitude or a finite 3-vector, got {gravity!r}")
    return vector


def _one_line(exc: Exception) -> str:
    text = " ".join(str(exc).split())
    return text[:300] if text else type(exc).__name__


@contextlib.contextmanager
def _quiet_native_stderr():
    """Silence what the C++ URDF parser prints on file descriptor 2 (its error is re-raised)."""
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):
        yield
        return
    try:
        with open(os.devnull, "w") as devnull:
            os.dup2(devnull.fileno(), 2)
            yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)
