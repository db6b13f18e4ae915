"""Mimic joints in any order: put every primary joint before its mimic joints before Pinocchio parses a URDF.

Pinocchio numbers a URDF's joints depth first from the root link, taking the child joints of
each link in the order of their *names* (the URDF parser keeps its joints in a map sorted by
name; the order in the file does not matter). It refuses a mimic joint numbered before its
primary joint ("The parent joint of the mimic joint is not in the kinematic tree"), so whether
a URDF loads depended on how its joints were named.

:func:`ordered_for_pinocchio` finds such a URDF and reorders it: at each link it sorts the
child joints topologically, so that the branch holding a primary joint comes before the
branch holding its mimic (otherwise by name, as Pinocchio does), and renames every joint of the
copy handed to Pinocchio with a prefix that makes the name order that order. The tree, the
origins, the axes and the couplings are unchanged; :func:`restore_names` gives the model's
joints and frames their names back. A URDF whose mimic joint is an ancestor of its primary (no
order can put the primary first), or whose couplings ask for contradictory orders, is refused
with a one-line :class:`~springbalance.errors.InputError` that names the mimic joint and its
primary.
"""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from typing import TYPE_CHECKING

from springbalance.errors import InputError

if TYPE_CHECKING:
    import pinocchio as pin

#: the prefix of a joint's temporary name: ``_sb<rank among its siblings>_<name>``
PREFIX = "_sb"


def ordered_for_pinocchio(text: str, where: str) -> tuple[str, dict[str, str]] | None:
    """The URDF ``text`` with its joints renamed so that Pinocchio numbers every primary joint
    before its mimic joints, and the map temporary name → joint name; ``None`` when the URDF
    already loads as it is (or declares no mimic joint). ``where`` names the URDF in errors."""
    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError:
        return None  # the parser reports it
    joints = {joint.get("name", ""): joint for joint in root.findall("joint")}
    pairs = [(name, _primary(joint)) for name, joint in joints.items() if joint.find("mimic") is not None]
    pairs = [
        (mimic, primary) for mimic, primary in pairs if primary in joints
    ]  # an unknown primary: the parser's error
    if not pairs:
        return None
    parent = {_link(joint, "child"): _link(joint, "parent") for joint in joints.values()}
    joint_of = {_link(joint, "child"): name for name, joint in joints.items()}
    children: dict[str, list[str]] = {}
    for name in sorted(joints):  # Pinocchio's order among siblings: by name
        children.setdefault(_link(joints[name], "parent"), []).append(name)
    numbered = _preorder(children, parent, {name: _link(joint, "child") for name, joint in joints.items()})
    if all(numbered.get(primary, -1) < numbered.get(mimic, -1) for mimic, primary in pairs):
        return None  # Pinocchio loads it as written
    paths = {name: _path(_link(joint, "child"), parent, joint_of) for name, joint in joints.items()}
    before: dict[str, set[str]] = {name: set() for name in joints}  # sibling joint -> siblings that must follow it
    for mimic, primary in pairs:
        first, second = paths[primary], paths[mimic]
        if primary in second:
            continue  # the primary is an ancestor of its mimic: always numbered first
        if mimic in first:
            raise InputError(
                f"{where}: mimic joint {mimic!r} is an ancestor of its primary joint {primary!r}, so Pinocchio "
                f"cannot number {primary!r} first; make {primary!r} the mimic of {mimic!r} (multiplier 1/m, "
                "offset -offset/m) or move the mimic joint below its primary"
            )
        fork = next(i for i, (a, b) in enumerate(zip(first, second)) if a != b)
        before[first[fork]].add(second[fork])
    ranks = {}
    for link, siblings in children.items():
        ranks.update({name: rank for rank, name in enumerate(_topological(siblings, before, pairs, where, link))})
    width = len(str(max(len(siblings) for siblings in children.values())))
    renamed = {name: f"{PREFIX}{ranks[name]:0{width}d}_{name}" for name in joints}
    for name, joint in joints.items():
        joint.set("name", renamed[name])
        mimic_element = joint.find("mimic")
        if mimic_element is not None:
            mimic_element.set("joint", renamed[mimic_element.get("joint", "")])
    return ElementTree.tostring(root, encoding="unicode"), {new: old for old, new in renamed.items()}


def restore_names(model: pin.Model, names: dict[str, str]) -> None:
    """Give the joints and frames of ``model`` their URDF names back (``names``: temporary → joint name)."""
    for index, name in enumerate(model.names):
        if name in names:
            model.names[index] = names[name]
    for frame in model.frames:
        if frame.name in names:
            frame.name = names[frame.name]


def _primary(joint: ElementTree.Element) -> str:
    mimic = joint.find("mimic")
    return "" if mimic is None else mimic.get("joint", "")


def _link(joint: ElementTree.Element, end: str) -> str:
    element = joint.find(end)
    return "" if element is None else element.get("link", "")


def _path(link: str, parent: dict[str, str], joint_of: dict[str, str]) -> list[str]:
    """The joints from the root link down to the joint whose child is ``link``."""
    path: list[str] = []
    while link in joint_of and len(path) <= len(joint_of):  # (a loop in a malformed URDF ends)
        path.append(joint_of[link])
        link = parent[link]
    return path[::-1]


def _preorder(children: dict[str, list[str]], parent: dict[str, str], child: dict[str, str]) -> dict[str, int]:
    """Each joint's number in Pinocchio's order (depth first from the root, siblings by name)."""
    roots = sorted(link for link in children if link not in parent)
    stack = [joint for root in reversed(roots) for joint in reversed(children[root])]
    numbers: dict[str, int] = {}
    while stack:
        joint = stack.pop()
        if joint in numbers:
            continue  # (a loop in a malformed URDF)
        numbers[joint] = len(numbers)
        stack.extend(reversed(children.get(child[joint], [])))
    return numbers


def _topological(
    siblings: list[str], before: dict[str, set[str]], pairs: list[tuple[str, str]], where: str, link: str
) -> list[str]:
    """``siblings`` (sorted by name) ordered so that each precedes the joints in its ``before`` set;
    by name where free."""
    members = set(siblings)
    waiting = {name: sum(name in before[other] for other in siblings) for name in siblings}
    order: list[str] = []
    while len(order) < len(siblings):
        ready = [name for name in siblings if name not in order and waiting[name] == 0]
        if not ready:
            mimic, primary = pairs[0]
            raise InputError(
                f"{where}: the mimic couplings below link {link!r} ask for contradictory joint orders "
                f"(mimic joint {mimic!r} of {primary!r} among them); Pinocchio needs every primary joint "
                "before its mimic joints: rename the joints or make one coupling's mimic its primary"
            )
        order.append(ready[0])
        for other in before[ready[0]] & members:
            waiting[other] -= 1
    return order
