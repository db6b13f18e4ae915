"""The mechanism: an immutable Pinocchio model plus the names springbalance needs.

A :class:`Mechanism` is built from a URDF file, a URDF string, an example-robot-data robot
name or an existing ``pinocchio.Model``. It knows its *degrees of freedom* (the one-DOF
joints that the workspace samples: revolute, continuous and prismatic; mimic joints follow
their primary joint) and its *bodies* (the URDF links, plus ``universe`` for the ground),
which are where spring ends attach.

Units: joint coordinates in rad (revolute, continuous) or m (prismatic); gravity in m/s².
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from springbalance.errors import InputError
from springbalance.model import robots, validation
from springbalance.model.joints import Joint, degrees_of_freedom
from springbalance.model.pseudo_bases import PseudoBase, pseudo_bases_from
from springbalance.model.urdf_build import build_model as _build

GROUND = "universe"
#: the largest magnitude of gravity [m/s²] taken (about 100 g): beyond it a number is a typo
MAX_GRAVITY = 1e3
#: the largest floor height accepted [m] (a height in millimetres given as metres is refused)
MAX_FLOOR = 100.0


class Mechanism:
    """A Pinocchio model with named degrees of freedom and bodies.

    Use the constructors :meth:`from_urdf`, :meth:`from_urdf_string`, :meth:`from_robot`
    or :meth:`from_model`. Each checks the arm's physics first (:mod:`springbalance.model.validation`:
    masses ≥ 0, inertias positive semi-definite within the triangle inequality, ordered joint
    limits) and raises :class:`~springbalance.errors.InputError` naming the link or joint and the
    attribute; ``validate=False`` loads a deliberately odd arm anyway (malformed numbers are
    always refused). The choice is kept in :attr:`source` (``"validate": false``).

    Attributes:
        model: the ``pinocchio.Model`` (gravity already set).
        joints: the degrees of freedom, in the order of the torque vector.
        source: how to rebuild this mechanism (saved with designs).
        floor: the height [m] of the floor (or table) the arm stands on, the world plane ``z = floor``, or None:
            a collision object below it that springs keep clear of (:mod:`springbalance.model.floor`).
    """

    def __init__(
        self,
        model: pin.Model,
        source: dict[str, Any] | None = None,
        gravity: npt.ArrayLike | None = None,
        validate: bool = True,
        floor: float | None = None,
    ) -> None:
        self.model = model.copy() if hasattr(model, "copy") else pin.Model(model)
        if gravity is not None:
            self.model.gravity.linear = _gravity_vector(gravity)
        self.source = dict(source or {"kind": "model"})
        if not validate:
            self.source["validate"] = False
        elif self.source.get("kind") == "model":  # a URDF was checked before Pinocchio read it
            validation.check_model(self.model, f"mechanism {self.model.name!r}")
        self.source["gravity"] = [float(v) for v in self.model.gravity.linear]
        self._floor = checked_floor(floor if floor is not None else self.source.get("floor"), self.model.name)
        if self._floor is not None:
            self.source["floor"] = self._floor
        self.joints = degrees_of_freedom(self.model)
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
    def from_urdf(
        cls,
        path: str | Path,
        gravity: npt.ArrayLike | None = None,
        mimic: bool = False,
        validate: bool = True,
        pseudo_bases: Iterable[str | dict | PseudoBase] | None = None,
        floor: float | None = None,
    ) -> Mechanism:
        """Load a URDF file. ``gravity``: magnitude g (then (0, 0, -g)) or a 3-vector [m/s²];
        ``validate``: check the physics (see the class documentation); ``pseudo_bases``: joints (names,
        ``{joint, mass [kg], com [m]}`` records or :class:`~springbalance.model.pseudo_bases.PseudoBase`) that get
        a pseudo-base ``pb_<joint>`` (:mod:`springbalance.model.pseudo_bases`; mimic joints are then coupled);
        ``floor``: the height [m] of the world plane the arm stands on, which springs keep clear of (see the class
        documentation)."""
        path = Path(path)
        where = f"URDF file {str(path)!r}"
        bases = pseudo_bases_from(pseudo_bases)
        text = validation.read_urdf(path)
        validation.check_urdf(text, where, physics=validate)
        model = _build(text, where, mimic, bases, path, str(path))
        source = {"kind": "urdf", "path": str(path.resolve()), "mimic": mimic or bool(bases), **_bases_record(bases)}
        return cls(model, source=source, gravity=gravity, validate=validate, floor=floor)

    @classmethod
    def from_urdf_string(
        cls,
        text: str,
        gravity: npt.ArrayLike | None = None,
        mimic: bool = False,
        validate: bool = True,
        pseudo_bases: Iterable[str | dict | PseudoBase] | None = None,
        floor: float | None = None,
    ) -> Mechanism:
        """Parse a URDF given as XML text (``validate``, ``pseudo_bases``, ``floor``: as :meth:`from_urdf`)."""
        if not isinstance(text, str):
            raise InputError(f"a URDF string must be text, got {type(text).__name__}")
        bases = pseudo_bases_from(pseudo_bases)
        validation.check_urdf(text, "URDF string", physics=validate)
        model = _build(text, "URDF string", mimic, bases, None, "URDF string")
        source = {"kind": "urdf_string", "text": text, "mimic": mimic or bool(bases), **_bases_record(bases)}
        return cls(model, source=source, gravity=gravity, validate=validate, floor=floor)

    @classmethod
    def from_robot(
        cls,
        name: str,
        gravity: npt.ArrayLike | None = None,
        mimic: bool = False,
        validate: bool = True,
        pseudo_bases: Iterable[str | dict | PseudoBase] | None = None,
        floor: float | None = None,
    ) -> Mechanism:
        """Load a robot of example-robot-data by name (``"ur5"``, ``"panda"``, ...; ``validate``, ``pseudo_bases``,
        ``floor``: as :meth:`from_urdf`)."""
        path = robots.robot_urdf(name)
        mechanism = cls.from_urdf(
            path, gravity=gravity, mimic=mimic, validate=validate, pseudo_bases=pseudo_bases, floor=floor
        )
        mechanism.source = {**mechanism.source, "kind": "robot", "robot": name}
        return mechanism

    @classmethod
    def from_model(cls, model: pin.Model, gravity: npt.ArrayLike | None = None, validate: bool = True) -> Mechanism:
        """Wrap an existing Pinocchio model (it is copied; ``validate``: check its masses, inertias and limits)."""
        return cls(model, source={"kind": "model"}, gravity=gravity, validate=validate)

    @classmethod
    def from_source(cls, source: dict[str, Any]) -> Mechanism:
        """Rebuild a mechanism from its :attr:`source` record (as saved in a design file)."""
        kind = source.get("kind")
        gravity = source.get("gravity")
        mimic = bool(source.get("mimic", False))
        options: dict[str, Any] = {"mimic": mimic, "validate": source.get("validate", True) is not False}
        options["pseudo_bases"] = source.get("pseudo_bases")
        options["floor"] = source.get("floor")
        if kind == "robot":
            return cls.from_robot(source["robot"], gravity=gravity, **options)
        if kind == "urdf":
            return cls.from_urdf(source["path"], gravity=gravity, **options)
        if kind == "urdf_string":
            return cls.from_urdf_string(source["text"], gravity=gravity, **options)
        raise InputError(f"cannot rebuild a mechanism from source kind {kind!r} (a bare Pinocchio model is not saved)")

    # ----------------------------------------------------------------- names
    @property
    def floor(self) -> float | None:
        """The height [m] of the floor the arm stands on (the world plane ``z = floor``), or None; fixed at
        construction, as the collision geometry is built with it."""
        return self._floor

    @property
    def name(self) -> str:
        """The model name (the URDF ``<robot name>``)."""
        return self.model.name

    @property
    def nv(self) -> int:
        """Number of degrees of freedom (columns of joint values and torques)."""
        return self.model.nv

    @property
    def joint_names(self) -> list[str]:
        """Names of the degrees of freedom, in the order of the torque vector."""
        return [joint.name for joint in self.joints]

    @property
    def body_names(self) -> list[str]:
        """Bodies that can carry a spring end: ``universe`` and every URDF link."""
        return list(self._frame_ids)

    @property
    def pseudo_bases(self) -> list[PseudoBase]:
        """The pseudo-bases added at load (:mod:`springbalance.model.pseudo_bases`), in the order given."""
        return pseudo_bases_from(self.source.get("pseudo_bases"))

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

    # ----------------------------------------------------------------- description
    def summary(self) -> dict[str, Any]:
        """What ``springbalance inspect`` prints: the bodies, joints and masses, as plain data.

        Units: masses in kg, lengths in m, joint limits in rad (revolute, continuous and the
        angle of a revolute mimic joint) or m (prismatic), gravity in m/s². The returned dict
        holds only str, float, int, bool, None, lists and dicts, so it is JSON-serialisable:

        - ``name``: the model name; ``source``: :attr:`source` (without the XML text of a
          mechanism built from a URDF string); ``gravity``: 3-vector [m/s²];
          ``dofs``: number of degrees of freedom (:attr:`nv`).
        - ``total_mass`` [kg]: every body of the URDF, ground bodies included;
          ``moving_mass`` [kg]: the bodies that are not ground.
        - ``ground``: the names of the bodies that cannot move, ``universe`` first (see :meth:`is_ground`).
        - ``bodies``: one dict per body of :attr:`body_names` (``universe`` first, then the URDF
          links in tree order): ``name``; ``mass`` [kg]; ``com``, the centre of mass in the body
          frame [m]; ``parent_joint``, the URDF joint whose child the body is (``None`` for
          ``universe`` and the root link; may be a fixed joint); ``moved_by``, the moving joint
          whose motion carries the body (``None`` for ground bodies); ``ground`` (bool).
        - ``joints``: one dict per URDF joint in tree order: ``name``; ``type``
          (``"revolute"``, ``"continuous"``, ``"prismatic"`` or ``"fixed"``); ``parent`` and
          ``child`` bodies; ``axis``, the unit axis in the joint frame (``None`` for a fixed
          joint); ``dof`` (bool: a degree of freedom, sampled by workspaces); ``lower`` and
          ``upper`` [rad or m], the range springbalance uses (``[-pi, pi]`` for continuous
          joints or missing limits, ``None`` for fixed and mimic joints); ``unit`` (``"rad"``,
          ``"m"`` or ``None``); ``mimic``: ``None`` or ``{"joint", "multiplier", "offset"}``
          (offset in rad or m), meaning ``q = multiplier * q[joint] + offset``. Mimic joints
          appear only when the mechanism was loaded with ``mimic=True``; otherwise they are
          independent degrees of freedom.

        Masses and centres of mass come from Pinocchio, which merges a link welded by a fixed
        joint into the body of its moving joint; they are split back per link here, and
        rounded to 1e-12 to hide the round-off of that split.
        """
        bodies = self._summary_bodies()
        masses = [body["mass"] for body in bodies]
        return {
            "name": self.name,
            "source": {key: value for key, value in self.source.items() if key != "text"},
            "gravity": [float(value) for value in self.gravity],
            "dofs": self.nv,
            "total_mass": _clean(sum(masses)),
            "moving_mass": _clean(sum(body["mass"] for body in bodies if not body["ground"])),
            "ground": [body["name"] for body in bodies if body["ground"]],
            "bodies": bodies,
            "joints": self._summary_joints(),
        }

    def _summary_bodies(self) -> list[dict[str, Any]]:
        """The ``bodies`` records of :meth:`summary`: per body, its own mass [kg] and centre of mass [m] (the
        links welded by fixed joints split back out of their Pinocchio body), parent joint and moving joint."""
        model = self.model
        frames = model.frames
        fixed_inertias = self._fixed_link_inertias()
        bodies = []
        for name, frame_id in self._frame_ids.items():
            frame = frames[frame_id]
            if frame_id == 0:  # universe
                inertia, parent_joint = pin.Inertia.Zero(), None
            else:
                parent = frames[frame.parentFrame]
                is_fixed_child = parent.type == pin.FrameType.FIXED_JOINT and frame.parentFrame != 0
                if is_fixed_child:
                    inertia = frame.placement.actInv(parent.placement.act(parent.inertia))
                else:
                    joint_inertia = model.inertias[frame.parentJoint]
                    welded = fixed_inertias.get(frame.parentJoint, [])
                    mass = joint_inertia.mass - sum(item.mass for item in welded)
                    first_moment = joint_inertia.mass * joint_inertia.lever - sum(
                        (item.mass * item.lever for item in welded), np.zeros(3)
                    )
                    lever = first_moment / mass if abs(mass) > 1e-12 else np.zeros(3)
                    inertia = frame.placement.actInv(pin.Inertia(mass, lever, np.eye(3)))
                parent_joint = (
                    parent.name
                    if parent.type in (pin.FrameType.JOINT, pin.FrameType.FIXED_JOINT) and frame.parentFrame != 0
                    else None
                )
            ground = self.is_ground(name)
            bodies.append(
                {
                    "name": name,
                    "mass": _clean(inertia.mass),
                    "com": [_clean(value) for value in inertia.lever],
                    "parent_joint": parent_joint,
                    "moved_by": None if ground else model.names[frame.parentJoint],
                    "ground": ground,
                }
            )
        return bodies

    def _summary_joints(self) -> list[dict[str, Any]]:
        """The ``joints`` records of :meth:`summary`, one per URDF joint in tree order (fixed joints included)."""
        frames = self.model.frames
        children = {frames[frame_id].parentFrame: name for name, frame_id in self._frame_ids.items() if frame_id}
        joints = []
        for frame_id, frame in enumerate(frames):
            if frame_id == 0 or frame.type not in (pin.FrameType.JOINT, pin.FrameType.FIXED_JOINT):
                continue
            record: dict[str, Any] = {
                "name": frame.name,
                "type": "fixed",
                "parent": frames[frame.parentFrame].name,
                "child": children.get(frame_id),
                "axis": None,
                "dof": False,
                "lower": None,
                "upper": None,
                "unit": None,
                "mimic": None,
            }
            if frame.type == pin.FrameType.JOINT:
                record.update(self._summary_moving_joint(frame))
            joints.append(record)
        return joints

    def _summary_moving_joint(self, frame: pin.Frame) -> dict[str, Any]:
        """The entries of a moving joint's :meth:`summary` record: unit axis in the joint frame, type, range
        [rad or m] of a degree of freedom, mimic coupling."""
        model = self.model
        mimics = dict(zip((int(i) for i in model.mimicking_joints), (int(i) for i in model.mimicked_joints)))
        dofs = {joint.name: joint for joint in self.joints}
        record: dict[str, Any] = {}
        joint_id = frame.parentJoint
        joint_model = model.joints[joint_id]
        data = joint_model.createData()
        joint_model.calc(data, pin.neutral(model))
        subspace = np.asarray(data.S, dtype=float).ravel()
        if joint_id in mimics:
            mimic = joint_model.extract()
            scaling = float(mimic.scaling)
            record["mimic"] = {
                "joint": model.names[mimics[joint_id]],
                "multiplier": scaling,
                "offset": float(mimic.offset),
            }
            if scaling:
                subspace = subspace / scaling  # a mimic joint's motion subspace is scaled
        angular = np.linalg.norm(subspace[3:]) > np.linalg.norm(subspace[:3])
        axis = subspace[3:] if angular else subspace[:3]
        norm = np.linalg.norm(axis)
        record["axis"] = [_clean(value / norm) for value in axis] if norm > 0 else None
        if frame.name in dofs:
            dof = dofs[frame.name]
            record.update(type=dof.kind, dof=True, lower=float(dof.lower), upper=float(dof.upper), unit=dof.unit)
        else:
            record.update(type="revolute" if angular else "prismatic")
        return record

    def _fixed_link_inertias(self) -> dict[int, list[pin.Inertia]]:
        """Per Pinocchio joint, the inertias (in the joint frame) of the links welded to it by fixed joints."""
        welded: dict[int, list[pin.Inertia]] = {}
        for frame_id, frame in enumerate(self.model.frames):
            if frame_id and frame.type == pin.FrameType.FIXED_JOINT:
                welded.setdefault(frame.parentJoint, []).append(frame.placement.act(frame.inertia))
        return welded

    # ----------------------------------------------------------------- coordinates
    def configurations(self, joint_values: npt.ArrayLike) -> np.ndarray:
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


def _bases_record(bases: list[PseudoBase]) -> dict[str, Any]:
    """``{"pseudo_bases": [records]}`` for a source with pseudo-bases, else nothing (sources stay as they were)."""
    return {"pseudo_bases": [base.to_dict() for base in bases]} if bases else {}


def _gravity_vector(gravity: npt.ArrayLike) -> np.ndarray:
    try:
        vector = np.asarray(gravity, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"gravity must be a magnitude or a finite 3-vector, got {gravity!r}") from None
    if vector.ndim == 0:
        vector = np.array([0.0, 0.0, -float(vector)])
    if vector.shape != (3,) or not np.all(np.isfinite(vector)):
        raise InputError(f"gravity must be a magnitude or a finite 3-vector, got {gravity!r}")
    if np.max(np.abs(vector)) > MAX_GRAVITY:
        raise InputError(f"gravity {gravity!r} is beyond {MAX_GRAVITY:g} m/s² (about 100 g); give it in m/s²")
    return vector


def _clean(value: float) -> float:
    """``value`` rounded to 1e-12, without a negative zero."""
    return float(round(float(value), 12)) + 0.0


def checked_floor(floor: object, name: str) -> float | None:
    """The floor's height [m] (a finite number), None for none; InputError naming the mechanism otherwise."""
    if floor is None:
        return None
    try:
        height = float(floor)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        height = float("nan")
    if isinstance(floor, bool) or not np.isfinite(height) or abs(height) > MAX_FLOOR:
        raise InputError(
            f"mechanism {name!r}: floor must be a finite height [m] of the world plane z = floor, within "
            f"±{MAX_FLOOR:g} m, got {floor!r}"
        )
    return height
