"""Checks of a URDF before it becomes a mechanism: numbers a parser reads, and physics an arm can have.

Two kinds of check, each reported as one :class:`~springbalance.errors.InputError` that names the
link or joint, the element and the attribute:

- **well-formed numbers** (always): every numeric attribute the URDF parser reads (masses,
  inertias, origins, axes, limits, mimic couplings, dynamics, geometry sizes) is a finite decimal
  number, with as many numbers as the attribute takes. The URDF parser drops an ``<inertial>``
  whose mass it cannot read and loads the link as massless, and reports a malformed limit only
  as "not a valid URDF model"; this check names the culprit instead.
- **physics** (unless switched off with ``validate=False``, config ``mechanism.validate: false``,
  ``springbalance inspect --no-validate``):

  - a mass [kg] is ≥ 0; a link is massless only where the URDF says so: no ``<inertial>``, or a
    mass of 0 with a zero inertia;
  - an inertia [kg·m²] is symmetric positive semi-definite (a point mass has a zero inertia) and
    its principal moments ``a ≤ b ≤ c`` meet the triangle inequality ``a + b ≥ c``;
  - a revolute or prismatic joint's limits are ordered, ``lower ≤ upper`` [rad or m] (equal
    limits, which is what a URDF without ``lower``/``upper`` gives, mean "no limits");
  - a moving joint's axis is not the zero vector.

  Tolerances allow for values rounded in the file: :data:`RELATIVE_TOLERANCE` of the largest
  principal moment plus :data:`ABSOLUTE_TOLERANCE`.

:func:`check_model` applies the physics checks to a ``pinocchio.Model`` built elsewhere, per joint
body (Pinocchio merges links welded by fixed joints into the body of their joint).
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ElementTree
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from springbalance.errors import InputError
from springbalance.files import read_input_text

if TYPE_CHECKING:
    import pinocchio as pin

#: a number as the URDF parser reads it: decimal, optional sign, fraction and exponent
NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
#: inertia checks: a principal moment may be negative, and the triangle inequality may fail, by this
#: fraction of the largest principal moment (values rounded in the file) ...
RELATIVE_TOLERANCE = 1e-3
#: ... plus this much [kg·m²]
ABSOLUTE_TOLERANCE = 1e-12
#: the opt-out, as the message says it
OPT_OUT = (
    "if the URDF means it, load it with validate=False (config: mechanism.validate: false; "
    "springbalance inspect --no-validate)"
)

#: numeric attributes the URDF parser reads: (element path below <link>/<joint>, attribute, how many numbers)
_LINK_NUMBERS = (
    ("inertial/origin", "xyz", 3),
    ("inertial/origin", "rpy", 3),
    ("inertial/mass", "value", 1),
    *(("inertial/inertia", key, 1) for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")),
    *((f"{kind}/origin", key, 3) for kind in ("visual", "collision") for key in ("xyz", "rpy")),
    *((f"{kind}/geometry/box", "size", 3) for kind in ("visual", "collision")),
    *(
        (f"{kind}/geometry/{shape}", key, 1)
        for kind in ("visual", "collision")
        for shape, key in (
            ("sphere", "radius"),
            ("cylinder", "radius"),
            ("cylinder", "length"),
            ("capsule", "radius"),
            ("capsule", "length"),
        )
    ),
    *((f"{kind}/geometry/mesh", "scale", 3) for kind in ("visual", "collision")),
)
_JOINT_NUMBERS = (
    ("origin", "xyz", 3),
    ("origin", "rpy", 3),
    ("axis", "xyz", 3),
    *(("limit", key, 1) for key in ("lower", "upper", "effort", "velocity")),
    *(("mimic", key, 1) for key in ("multiplier", "offset")),
    *(("dynamics", key, 1) for key in ("damping", "friction")),
    *(("safety_controller", key, 1) for key in ("soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity")),
    *(("calibration", key, 1) for key in ("rising", "falling")),
)
_MOVING = ("revolute", "continuous", "prismatic")
_INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


def read_urdf(path: str | Path) -> str:
    """The text of the URDF file ``path``; InputError when it is missing, a directory, unreadable
    (permission denied) or not UTF-8 text."""
    return read_input_text(path, "URDF file", InputError)


def check_urdf(text: str, where: str, physics: bool = True) -> None:
    """Check the URDF ``text`` (see the module documentation); ``where`` starts the message
    (e.g. ``URDF file 'arm.urdf'``). ``physics=False`` checks the numbers' syntax only.

    Raises:
        InputError: the XML is not well formed, a numeric attribute is malformed, or (with
            ``physics``) a mass, inertia, joint limit or axis is impossible.
    """
    try:
        root = ElementTree.fromstring(text.encode("utf-8") if isinstance(text, str) else text)
    except ElementTree.ParseError as error:
        raise InputError(f"{where} could not be parsed: not well-formed XML ({error})") from None
    if root.tag != "robot":
        raise InputError(f"{where}: the root element is <{root.tag}>, not <robot>")
    for kind, table in (("link", _LINK_NUMBERS), ("joint", _JOINT_NUMBERS)):
        for element in root.iter(kind):
            for path, key, count in table:
                for child in element.findall(path):
                    _numbers(child, key, count, f"{where}: {kind} {element.get('name')!r}: <{path.split('/')[-1]}>")
    if not physics:
        return
    for link in root.iter("link"):
        _check_inertial(link, f"{where}: link {link.get('name')!r}")
    for joint in root.iter("joint"):
        _check_joint(joint, f"{where}: joint {joint.get('name')!r}")


def check_model(model: pin.Model, where: str) -> None:
    """Physics checks of a ``pinocchio.Model`` (per joint body, limits of the degrees of freedom)."""
    for joint_id in range(1, model.njoints):
        inertia = model.inertias[joint_id]
        label = f"{where}: body of joint {model.names[joint_id]!r}"
        mass = float(inertia.mass)
        _check_mass_and_inertia(
            mass, np.array(inertia.inertia, dtype=float), label, f"mass {mass:g}", "rotational inertia"
        )
    lower, upper = np.asarray(model.lowerPositionLimit), np.asarray(model.upperPositionLimit)
    for joint_id in range(1, model.njoints):
        joint = model.joints[joint_id]
        if joint.nq != 1:
            continue
        lo, up = float(lower[joint.idx_q]), float(upper[joint.idx_q])
        if math.isnan(lo) or math.isnan(up):
            raise InputError(f"{where}: joint {model.names[joint_id]!r}: a position limit is nan")
        if lo > up:
            raise InputError(
                f"{where}: joint {model.names[joint_id]!r}: lower position limit {lo:g} > upper {up:g}; " + OPT_OUT
            )


# ---------------------------------------------------------------------- pieces
def _numbers(element: ElementTree.Element, key: str, count: int, where: str) -> list[float] | None:
    """The numbers of attribute ``key`` of ``element`` (None when absent); InputError when malformed."""
    text = element.get(key)
    if text is None:
        return None
    parts = text.split()
    values = []
    if len(parts) == count:
        for part in parts:
            if not NUMBER.fullmatch(part):
                break
            value = float(part)
            if not math.isfinite(value):
                break
            values.append(value)
    if len(values) != count:
        what = "a finite number" if count == 1 else f"{count} finite numbers"
        raise InputError(f"{where} {key}={text!r} is not {what}")
    return values


def _check_inertial(link: ElementTree.Element, where: str) -> None:
    inertial = link.find("inertial")
    if inertial is None:
        return  # no <inertial>: a massless link, as the URDF says
    mass_element = inertial.find("mass")
    if mass_element is None or mass_element.get("value") is None:
        raise InputError(f"{where}: <inertial> has no <mass value=...>")
    numbers = _numbers(mass_element, "value", 1, where)
    assert numbers is not None  # the value attribute is present (checked above)
    mass = numbers[0]
    inertia_element = inertial.find("inertia")
    values = {key: 0.0 for key in _INERTIA_KEYS}
    if inertia_element is not None:
        for key in _INERTIA_KEYS:
            number = _numbers(inertia_element, key, 1, f"{where}: <inertia>")
            if number is not None:
                values[key] = number[0]
    matrix = np.array(
        [
            [values["ixx"], values["ixy"], values["ixz"]],
            [values["ixy"], values["iyy"], values["iyz"]],
            [values["ixz"], values["iyz"], values["izz"]],
        ]
    )
    _check_mass_and_inertia(
        mass,
        matrix,
        where,
        f"<mass value={mass_element.get('value')!r}>",
        "<inertia " + " ".join(f"{key}={values[key]:g}" for key in _INERTIA_KEYS) + ">",
    )


def _check_mass_and_inertia(mass: float, matrix: np.ndarray, where: str, mass_text: str, inertia_text: str) -> None:
    if not math.isfinite(mass) or mass < 0:
        raise InputError(
            f"{where}: {mass_text} is {'negative' if mass < 0 else 'not finite'}; a mass is a finite "
            f"number ≥ 0 [kg]; " + OPT_OUT
        )
    if not np.all(np.isfinite(matrix)):
        raise InputError(f"{where}: {inertia_text} is not finite; " + OPT_OUT)
    diagonal = np.diag(matrix)
    largest = float(np.max(np.abs(matrix)))
    if mass == 0:
        if largest > ABSOLUTE_TOLERANCE:
            raise InputError(
                f"{where}: {mass_text} but a non-zero {inertia_text}; a massless link has no inertia "
                f"[kg·m²]; " + OPT_OUT
            )
        return
    names = ("ixx", "iyy", "izz")
    for name, value in zip(names, diagonal):
        if value < -ABSOLUTE_TOLERANCE:
            raise InputError(
                f"{where}: inertia {name}={value:g} is negative: {inertia_text} [kg·m²] is not positive "
                f"semi-definite; " + OPT_OUT
            )
    moments = np.linalg.eigvalsh((matrix + matrix.T) / 2)
    tolerance = RELATIVE_TOLERANCE * float(np.max(np.abs(moments))) + ABSOLUTE_TOLERANCE
    if moments[0] < -tolerance:
        raise InputError(
            f"{where}: {inertia_text} is not positive semi-definite: principal moments "
            f"{', '.join(f'{m:.4g}' for m in moments)} [kg·m²]; " + OPT_OUT
        )
    a, b, c = np.sort(np.maximum(moments, 0.0))
    if a + b < c - tolerance:
        raise InputError(
            f"{where}: {inertia_text} violates the triangle inequality: principal moments "
            f"{a:.4g} + {b:.4g} < {c:.4g} [kg·m²], which no rigid body has; " + OPT_OUT
        )


def _check_joint(joint: ElementTree.Element, where: str) -> None:
    kind = joint.get("type")
    if kind not in _MOVING:
        return
    axis = joint.find("axis")
    if axis is not None:
        values = _numbers(axis, "xyz", 3, f"{where}: <axis>")
        if values is not None and not any(values):
            raise InputError(f"{where}: <axis xyz={axis.get('xyz')!r}> is the zero vector; " + OPT_OUT)
    limit = joint.find("limit")
    if limit is None or kind == "continuous":
        return
    lower = (_numbers(limit, "lower", 1, f"{where}: <limit>") or [0.0])[0]
    upper = (_numbers(limit, "upper", 1, f"{where}: <limit>") or [0.0])[0]
    if lower > upper:
        unit = "m" if kind == "prismatic" else "rad"
        raise InputError(
            f"{where}: <limit lower={limit.get('lower')!r} upper={limit.get('upper')!r}>: lower > upper "
            f"[{unit}]; " + OPT_OUT
        )
