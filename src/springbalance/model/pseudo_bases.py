r"""Pseudo-bases: auxiliary bodies that sit at a joint's origin and keep the world's orientation.

A pseudo-base at joint :math:`J` (body ``pb_<J>``) is the spring anchor of seed 004 (ch. 4): realised by
parallelograms, it follows the origin of joint :math:`J` while its orientation stays the world's, so a
zero-free-length spring from it to the link that :math:`J` moves balances that link exactly
(docs/model.md §1.1). It is written into the URDF as the mimic "undo" chain, before Pinocchio loads it.

Let the joints from the root link to :math:`J`'s parent link be :math:`j_1 … j_m`, joint :math:`j_k` with
the fixed origin rotation :math:`F_k` and, when it moves, the rotation :math:`\mathrm{Rot}(a_k, q_k)`
about its axis :math:`a_k`. The parent link's orientation is
:math:`R_P = F_1 \mathrm{Rot}(a_1, q_1) \cdots F_m \mathrm{Rot}(a_m, q_m)` (a fixed joint contributes
:math:`F_k` alone). The chain hangs from the parent link at :math:`J`'s origin point and undoes these
factors in reverse order: per moving joint :math:`j_k` (from :math:`k = m` down to 1) one revolute joint
about :math:`a_k` that mimics :math:`j_k` with multiplier −1, each origin rotation :math:`F_k^T` folded into
the next joint's origin. Since :math:`\mathrm{Rot}(a, q)\,\mathrm{Rot}(a, -q) = I` and
:math:`F F^T = I`, the product telescopes to :math:`R_P \mathrm{Rot}(a_m, -q_m) F_m^T \cdots = I`
for every pose, whatever the axes; every chain joint sits at one point, so the position is :math:`J`'s
origin. The chain's links are massless; the pseudo-base carries ``mass`` [kg] at ``com`` [m], a point in
its frame (world-aligned axes, origin at :math:`J`'s origin): that of the parallelograms realising it, which
the user gives (default 0 kg: the arm is balanced as if they were weightless), with the rotational inertia
of a solid sphere of radius :data:`SPHERE_RADIUS`.

**Vertical only** (``keep="vertical"``): where only gravity's direction matters, the pseudo-base need only keep
the world's vertical :math:`\hat z`. Walking from the root, let :math:`G` be the product of the origin rotations
so far; while every moving joint's axis :math:`a_k` has :math:`G a_k = \pm\hat z` (a vertical axis, such as a
KR-like arm's first yaw), :math:`\mathrm{Rot}(a_k, q) = G^T \mathrm{Rot}(\hat z, \pm q) G` and the prefix
product is :math:`R_{p} = \mathrm{Rot}(\hat z, \psi) G_p`. Those leading vertical joints get no mimic joint;
their origin rotations are still undone, so the chain ends at :math:`\mathrm{Rot}(\hat z, \psi) G_p G_p^T =
\mathrm{Rot}(\hat z, \psi)`: the body turns about the vertical with them and its :math:`z` axis stays
:math:`\hat z` (docs/model.md §1.1 says when that suffices for exact balance).

Names: the pseudo-base link ``pb_<J>``; the mimic joints ``pb_<J>__undo_<j_k>``, the fixed joints
``pb_<J>__unrotate_<j_k>_<r|p|y>`` (one per non-zero origin angle) and ``pb_<J>__fix``, each with its child link
``<joint name>_link``; none may clash with a name of the URDF. Prismatic joints between the root and
:math:`J` are refused (a parallelogram does not pass a slider).
"""

from __future__ import annotations

import dataclasses
import math
import xml.etree.ElementTree as ElementTree
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
import pinocchio as pin

from springbalance.errors import InputError
from springbalance.model.native import quiet_native_stderr

__all__ = [
    "PseudoBase",
    "add_pseudo_bases",
    "is_chain_link",
    "KEEPS",
    "pseudo_base_body",
    "pseudo_base_model",
    "pseudo_bases_from",
    "vertical_prefix",
]

#: the radius [m] of the solid sphere whose rotational inertia the pseudo-base gets (static torques do not depend
#: on it; MuJoCo refuses a positive mass with a zero inertia)
SPHERE_RADIUS = 0.02
#: the keys of a pseudo-base record (config ``mechanism.pseudo_bases[i]``)
KEYS = ("joint", "mass", "com", "keep")
#: what a pseudo-base keeps of the world's orientation: all of it, or only the vertical (module docstring)
KEEPS = ("orientation", "vertical")
#: how far [-] from ±ẑ a joint axis (a unit vector, world-aligned at zero pose) may be and still count as vertical
VERTICAL_TOLERANCE = 1e-12


def pseudo_base_body(joint: str) -> str:
    """The name of the pseudo-base body at joint ``joint``: ``pb_<joint>``."""
    return f"pb_{joint}"


@dataclasses.dataclass(frozen=True)
class PseudoBase:
    """A pseudo-base at the origin of joint ``joint``, keeping the world's orientation (or only its vertical).

    Attributes:
        joint: the URDF joint at whose origin it sits (the body is ``pb_<joint>``).
        mass: the mass [kg] of the pseudo-base and the parallelograms that realise it (≥ 0).
        com: its centre of mass [m] in the pseudo-base frame (world-aligned axes, origin at the joint's origin;
            with ``keep="vertical"`` the frame turns about the vertical with the arm's leading vertical joints).
        keep: ``"orientation"`` (the world's orientation) or ``"vertical"`` (only the world's z axis: the leading
            vertical-axis joints are not undone; module docstring).
    """

    joint: str
    mass: float = 0.0
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    keep: str = "orientation"

    @property
    def body(self) -> str:
        """The body name ``pb_<joint>`` that springs anchor on."""
        return pseudo_base_body(self.joint)

    def to_dict(self) -> dict[str, Any]:
        """The record ``{joint, mass [kg], com [m]}`` (as a config or a design file holds it), with
        ``keep: vertical`` when it keeps only the vertical."""
        record: dict[str, Any] = {"joint": self.joint, "mass": self.mass, "com": list(self.com)}
        return {**record, "keep": self.keep} if self.keep != "orientation" else record


def pseudo_bases_from(items: Iterable[Any] | None, where: str = "pseudo_bases") -> list[PseudoBase]:
    """:class:`PseudoBase` objects from joint names, records ``{joint, mass?, com?}`` or pseudo-bases.

    Raises:
        InputError: a malformed item, a negative or non-finite mass [kg] or centre of mass [m], or a joint
            given twice; the message names ``where[i]`` and the value.
    """
    if items is None:
        return []
    if isinstance(items, (str, Mapping)) or not isinstance(items, Iterable):
        raise InputError(f"{where}: expected a list of joint names or {{joint, mass, com}} records, got {items!r}")
    bases: list[PseudoBase] = []
    for index, item in enumerate(items):
        bases.append(_pseudo_base(item, f"{where}[{index}]"))
        if any(base.joint == bases[-1].joint for base in bases[:-1]):
            raise InputError(f"{where}[{index}].joint: joint {bases[-1].joint!r} has a pseudo-base already")
    return bases


def _pseudo_base(item: Any, where: str) -> PseudoBase:
    if isinstance(item, PseudoBase):
        item = item.to_dict()
    if isinstance(item, str):
        item = {"joint": item}
    if not isinstance(item, Mapping):
        raise InputError(f"{where}: expected a joint name or a {{joint, mass, com}} record, got {item!r}")
    unknown = [key for key in item if key not in KEYS]
    if unknown:
        raise InputError(f"{where}: unknown key {unknown[0]!r}; valid keys: {', '.join(KEYS)}")
    joint = item.get("joint")
    if not isinstance(joint, str) or not joint:
        raise InputError(f"{where}.joint: expected a joint name, got {joint!r}")
    mass = item.get("mass", 0.0)
    if isinstance(mass, bool) or not isinstance(mass, (int, float)) or not math.isfinite(mass) or mass < 0:
        raise InputError(f"{where}.mass: expected a finite mass ≥ 0 [kg], got {mass!r}")
    given = item.get("com", (0.0, 0.0, 0.0))
    com = [] if isinstance(given, (str, Mapping)) or not isinstance(given, Iterable) else list(given)
    if len(com) != 3 or not all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in com
    ):
        raise InputError(f"{where}.com: expected three finite numbers [m], got {item.get('com')!r}")
    keep = item.get("keep", "orientation")
    if keep not in KEEPS:
        raise InputError(f"{where}.keep: expected 'orientation' or 'vertical', got {keep!r}")
    return PseudoBase(joint, float(mass), (float(com[0]), float(com[1]), float(com[2])), keep)


def add_pseudo_bases(text: str, bases: Iterable[PseudoBase], where: str = "pseudo_bases") -> str:
    """The URDF text ``text`` with the undo chain of every pseudo-base appended (see the module docstring).

    The source text is kept byte for byte; the new elements go before the closing ``</robot>``.

    Raises:
        InputError: an unknown joint, a prismatic joint between the root and it, a name already taken,
            naming ``where[i]`` and the value.
    """
    bases = list(bases)
    if not bases:
        return text
    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError as error:
        raise InputError(f"{where}: the URDF could not be parsed: {error}") from None
    joints = {element.get("name"): element for element in root.findall("joint")}
    names = {element.get("name") for element in root.findall("link")} | set(joints)
    by_child = {_child(element): element for element in joints.values()}
    elements: list[str] = []
    for index, base in enumerate(bases):
        label = f"{where}[{index}].joint"
        if base.joint not in joints:
            raise InputError(f"{label}: unknown joint {base.joint!r}; joints: {', '.join(map(str, joints))}")
        chain = _chain_to(joints[base.joint], by_child, label)
        new = _chain_elements(base, joints[base.joint], chain)
        taken = sorted(set(new) & names)
        if taken:
            raise InputError(f"{label}: pseudo-base of {base.joint!r} needs the name {taken[0]!r}, which is taken")
        names |= set(new)
        elements.extend(new.values())
    end = text.rfind("</robot>")
    if end < 0:
        raise InputError(f"{where}: the URDF has no closing </robot>")
    return text[:end] + "\n".join(elements) + "\n" + text[end:]


def is_chain_link(link: str, bases: Iterable[PseudoBase]) -> bool:
    """True when ``link`` is a massless link of one of the undo chains of ``bases`` (not the pseudo-base itself)."""
    return any(link.startswith(f"{base.body}__") for base in bases)


def pseudo_base_model(text: str, bases: list[PseudoBase], where: str, mimic: bool) -> pin.Model:
    """The Pinocchio model of the URDF ``text`` with ``bases`` added (mimic joints coupled).

    The chains need ``mimic=True``; a URDF with mimic joints of its own loaded with ``mimic=False`` is refused
    (its mimic joints would change meaning silently).
    """
    if not mimic and any(element.find("mimic") is not None for element in ElementTree.fromstring(text).iter("joint")):
        raise InputError(
            f"{where}: pseudo_bases couple mimic joints, and this URDF declares its own; give mimic: true "
            "(Python: mimic=True) to couple them too"
        )
    full = add_pseudo_bases(text, bases, f"{where}: pseudo_bases")
    try:
        with quiet_native_stderr():
            return pin.buildModelFromXML(full, mimic=True)
    except Exception as exc:  # Pinocchio raises RuntimeError/ValueError with C++ text
        message = " ".join(str(exc).split())[:300]
        raise InputError(f"{where}: the URDF with pseudo-bases could not be parsed: {message}") from None


def _child(joint: ElementTree.Element) -> str | None:
    child = joint.find("child")
    return None if child is None else child.get("link")


def _chain_to(joint: ElementTree.Element, by_child: dict[str | None, ElementTree.Element], label: str) -> list:
    """The joints from the root link to ``joint``'s parent link, root first; a prismatic one is refused."""
    chain: list[ElementTree.Element] = []
    parent = joint.find("parent")
    link = None if parent is None else parent.get("link")
    while link in by_child:
        element = by_child[link]
        if element.get("type") == "prismatic" or element.get("type") == "floating" or element.get("type") == "planar":
            raise InputError(
                f"{label}: {joint.get('name')!r} lies beyond the {element.get('type')} joint {element.get('name')!r}; "
                "a pseudo-base keeps its orientation through revolute and fixed joints only"
            )
        chain.insert(0, element)
        parent = element.find("parent")
        link = None if parent is None else parent.get("link")
        if len(chain) > len(by_child):
            raise InputError(f"{label}: the URDF's joints form a loop")
    return chain


def _chain_elements(base: PseudoBase, joint: ElementTree.Element, chain: list) -> dict[str, str]:
    """Name → XML text of the links and joints of ``base``'s undo chain: per joint of ``chain`` (from the
    last), a mimic joint undoing its motion, then fixed joints undoing its origin rotation one angle at a time
    (``Rz(y) Ry(p) Rx(r)`` is undone by ``Rx(-r) Ry(-p) Rz(-y)``: exact, no conversion back to rpy)."""
    body = base.body
    vertical = vertical_prefix(chain) if base.keep == "vertical" else set()
    steps: list[tuple[str, str, str]] = []  # (joint name, rpy text, what follows the origin)
    for element in reversed(chain):
        primary = element.get("name")
        kind = element.get("type")
        if kind in ("revolute", "continuous") and primary not in vertical:
            axis_element = element.find("axis")
            axis = "1 0 0" if axis_element is None else axis_element.get("xyz", "1 0 0")
            limit = '<limit effort="0" velocity="0" lower="-1e9" upper="1e9"/>' if kind == "revolute" else ""
            tail = f'<axis xyz="{axis}"/>{limit}<mimic joint="{primary}" multiplier="-1" offset="0"/>'
            steps.append((f"{body}__undo_{primary}", "0 0 0", tail))
        for slot, angle in enumerate(_rpy(element)):
            if angle:
                angles = ["0", "0", "0"]
                angles[slot] = repr(-angle)
                steps.append((f"{body}__unrotate_{primary}_{'rpy'[slot]}", " ".join(angles), ""))
    steps.append((f"{body}__fix", "0 0 0", ""))
    origin = joint.find("origin")
    point = "0 0 0" if origin is None else origin.get("xyz", "0 0 0")
    parent = joint.find("parent").get("link")  # type: ignore[union-attr]
    elements: dict[str, str] = {}
    for index, (name, rpy, tail) in enumerate(steps):
        child = body if index == len(steps) - 1 else f"{name}_link"
        kind = "fixed" if not tail else ("revolute" if "<limit" in tail else "continuous")
        elements[name] = (
            f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{point if index == 0 else "0 0 0"}" rpy="{rpy}"/>{tail}</joint>'
        )
        if child != body:
            elements[child] = f'<link name="{child}"/>'
        parent = child
    com = " ".join(repr(v) for v in base.com)
    moment = repr(0.4 * base.mass * SPHERE_RADIUS**2)  # a solid sphere: (2/5) m r² [kg·m²]
    elements[body] = (
        f'<link name="{body}"><inertial><origin xyz="{com}" rpy="0 0 0"/><mass value="{base.mass!r}"/>'
        f'<inertia ixx="{moment}" ixy="0" ixz="0" iyy="{moment}" iyz="0" izz="{moment}"/></inertial></link>'
    )
    return elements


def vertical_prefix(chain: list) -> set[str]:
    """The names of the leading moving joints of ``chain`` (root first) whose axes stay world-vertical at every
    pose: with ``G`` the product of the origin rotations so far, ``G a = ±ẑ`` (module docstring)."""
    names: set[str] = set()
    turn = np.eye(3)
    for element in chain:
        roll, pitch, yaw = _rpy(element)
        turn = turn @ pin.rpy.rpyToMatrix(roll, pitch, yaw)
        if element.get("type") not in ("revolute", "continuous"):
            continue
        axis_element = element.find("axis")
        axis = np.array(
            [float(v) for v in ("1 0 0" if axis_element is None else axis_element.get("xyz", "1 0 0")).split()]
        )
        direction = turn @ (axis / np.linalg.norm(axis))
        if np.max(np.abs(direction[:2])) > VERTICAL_TOLERANCE:
            break
        names.add(str(element.get("name")))
    return names


def _rpy(joint: ElementTree.Element) -> tuple[float, float, float]:
    """The (roll, pitch, yaw) [rad] of a URDF joint's origin, ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
    origin = joint.find("origin")
    roll, pitch, yaw = (float(v) for v in ("0 0 0" if origin is None else origin.get("rpy", "0 0 0")).split())
    return roll, pitch, yaw
