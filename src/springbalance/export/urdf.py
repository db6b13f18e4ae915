r"""Export a balanced arm as a URDF with the spring anchors and records.

``export_urdf(design, "balanced.urdf")`` writes

- the original URDF unchanged (every element and number as in the source file; relative mesh
  paths made absolute so the file can live anywhere, ``package://`` paths kept or, with
  ``resolve_packages=True``, replaced by absolute paths of example-robot-data's folders);
- for every end of every two-point spring a massless link ``<spring>_anchor_<end>``, fixed to
  its body at the anchor point by the joint ``<spring>_anchor_<end>_joint`` (written by
  yourdfpy; an end on ``universe`` hangs from the URDF's root link, whose frame is the world);
- per spring one namespaced element ``<springbalance:spring>`` (namespace :data:`URDF_NAMESPACE`)
  with the law, its parameter values [SI] and the names of its anchor links as attributes,
  and the spring's full record as JSON text; the same records go to the sidecar
  ``balanced.springs.json``.

The original elements are copied from the source XML rather than re-serialised, so that
joint origins keep their exact text (a rotation written back from a matrix differs in the
last bits). :func:`springs_from_urdf` reads the springs back, with the anchor points taken from
the anchor joints' origins (:func:`springbalance.io.urdf.springs_from_urdf`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

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
from springbalance.model.mechanism import Mechanism

__all__ = ["SIDECAR_FORMAT", "URDF_NAMESPACE", "export_urdf", "root_link", "sidecar_path", "urdf_strings"]

URDF_NAMESPACE = "urn:springbalance:urdf-spring:1"
SIDECAR_FORMAT = "springbalance-urdf-springs/1"


def export_urdf(
    design: EvaluatedDesign, path: str | Path, resolve_packages: bool = False, sidecar: bool = True
) -> ExportReport:
    """Write the design's URDF with anchor links and spring records; see the module docstring.

    ``resolve_packages``: replace ``package://`` mesh paths by absolute paths (example-robot-data's
    folders, :func:`springbalance.model.robots.package_directories`); by default they are kept.
    ``sidecar``: also write ``<stem>.springs.json`` next to the URDF. Raises
    :class:`~springbalance.errors.InputError` (nothing written) when a name is taken or the
    written file does not read back.
    """
    path = Path(path)
    xml, record = urdf_strings(design, path.name, resolve_packages)
    files = [write_text_atomic(path, xml)]
    if sidecar:
        files.append(write_text_atomic(sidecar_path(path), record))
    return ExportReport(path, files, law_warnings(design))


def urdf_strings(
    design: EvaluatedDesign, name: str = "balanced.urdf", resolve_packages: bool = False
) -> tuple[str, str]:
    """(URDF text, sidecar JSON text) of :func:`export_urdf`, checked to load back."""
    from lxml import etree

    mechanism = design.problem.mechanism
    text, folder = source_urdf(mechanism)
    try:
        root = etree.fromstring(text.encode(), parser=etree.XMLParser(remove_blank_text=False))
    except etree.XMLSyntaxError as error:
        raise InputError(f"the design's URDF could not be parsed: {error}") from None
    _rewrite_mesh_paths(root, folder, resolve_packages)

    # the namespaced records: the root gets the namespace declaration
    robot = etree.Element("robot", nsmap={"springbalance": URDF_NAMESPACE})
    for key, value in root.attrib.items():
        robot.set(key, value)
    robot.text, robot.tail = root.text, root.tail
    for child in list(root):
        robot.append(child)
    records = _add_springs(robot, design)
    etree.indent(robot, space="  ")
    xml = etree.tostring(robot, xml_declaration=True, encoding="utf-8", pretty_print=True).decode()
    _check_urdf(xml, mechanism)
    sidecar = {
        "format": SIDECAR_FORMAT,
        "urdf": name,
        "namespace": URDF_NAMESPACE,
        "gravity": mechanism.gravity.tolist(),
        "mimic": bool(mechanism.source.get("mimic", False)),
        "joints": mechanism.joint_names,
        "springs": records,
    }
    return xml, json.dumps(sidecar, indent=1) + "\n"


def _add_springs(root: Any, design: EvaluatedDesign) -> list[dict]:
    """Append to the URDF tree ``root`` a ``<springbalance:spring>`` record per spring, then the anchor links
    and joints of every end; returns the saved records (the anchor points [m] in their bodies' frames)."""
    from lxml import etree

    links = {element.get("name") for element in root.findall("link")}
    joints = {element.get("name") for element in root.findall("joint")}
    base = root_link(root)
    anchor_elements = []
    records = []
    for spring, record, values in zip(design.problem.springs, design.fixed_springs(), design.springs):
        saved = record.to_dict()
        attributes = {"name": spring.name, "type": spring.kind}
        for key in spring.parameter_units:
            attributes[key] = number(values[key])
        if "joint" in values:
            attributes["joint"] = values["joint"]
        for end in spring.anchors:
            link_name = anchor_link_name(spring_name(spring), end)
            joint_name = link_name + "_joint"
            if link_name in links or joint_name in joints:
                raise InputError(
                    f"cannot add the anchor link {link_name!r}: the URDF already has a link or joint "
                    f"called {link_name!r} or {joint_name!r}"
                )
            body = values[end]["body"]
            parent = base if body == GROUND else body
            anchor_elements += _anchor_elements(link_name, joint_name, parent, values[end]["point"])
            attributes[f"anchor_{end}"] = link_name
            entry = {"body": body, "point": [float(v) for v in values[end]["point"]], "link": link_name}
            if saved.get("type") == "routed":  # the path's points, in order a, via1 …, b
                index = list(spring.anchors).index(end)
                saved["path"][index] = {
                    **entry,
                    **({"pulley": values[end]["pulley"]} if "pulley" in values[end] else {}),
                }
            else:
                saved[end] = entry
        element = etree.SubElement(root, f"{{{URDF_NAMESPACE}}}spring", attrib=attributes)
        element.text = json.dumps(saved)
        records.append(saved)
    for element in anchor_elements:
        root.append(element)
    return records


def sidecar_path(urdf_path: str | Path) -> Path:
    """``balanced.urdf`` → ``balanced.springs.json``."""
    urdf_path = Path(urdf_path)
    return urdf_path.with_name(urdf_path.stem + ".springs.json")


def _anchor_elements(link_name: str, joint_name: str, parent: str, point: Iterable[float]) -> list:
    """The massless link and its fixed joint at ``point`` [m] of ``parent``, written by yourdfpy."""
    import yourdfpy
    from lxml import etree

    origin = np.eye(4)
    origin[:3, 3] = np.asarray(point, dtype=float)
    writer = yourdfpy.URDF(robot=yourdfpy.Robot(name="anchor"), build_scene_graph=False, load_meshes=False)
    holder = etree.Element("robot")
    writer._write_link(holder, yourdfpy.Link(name=link_name))
    writer._write_joint(
        holder, yourdfpy.Joint(name=joint_name, type="fixed", parent=parent, child=link_name, origin=origin)
    )
    elements = list(holder)
    # yourdfpy writes str(float), which reads back exactly; keep the rpy text plain zeros
    for element in elements:
        for origin_element in element.iter("origin"):
            origin_element.set("xyz", vector(point))
            origin_element.set("rpy", "0 0 0")
    return elements


def root_link(root: Any) -> str:
    """The name of the one root link of the URDF tree ``root`` (an lxml element)."""
    children = {joint.find("child").get("link") for joint in root.findall("joint") if joint.find("child") is not None}
    roots = [link.get("name") for link in root.findall("link") if link.get("name") not in children]
    if len(roots) != 1:
        raise InputError(f"the URDF has {len(roots)} root links ({', '.join(roots)}); expected one")
    return roots[0]


def _rewrite_mesh_paths(root: Any, folder: Path | None, resolve_packages: bool) -> None:
    for mesh in root.iter("mesh"):
        filename = mesh.get("filename")
        if not filename:
            continue
        if filename.startswith("package://"):
            if resolve_packages:
                resolved = resolve_package(filename, robots.package_directories())
                if resolved is not None:
                    mesh.set("filename", str(resolved))
        elif filename.startswith("file://"):
            continue
        elif not os.path.isabs(filename) and folder is not None:
            mesh.set("filename", str((folder / filename).resolve()))


def _check_urdf(xml: str, mechanism: Mechanism) -> None:
    """The written URDF loads in Pinocchio and yourdfpy (as ``mechanism`` was loaded: mimic joints, validation)."""
    import io

    import yourdfpy

    try:
        source = mechanism.source
        Mechanism.from_urdf_string(
            xml, mimic=bool(source.get("mimic", False)), validate=source.get("validate", True) is not False
        )
        yourdfpy.URDF.load(io.BytesIO(xml.encode()), build_scene_graph=False, load_meshes=False)
    except Exception as error:
        raise InputError(f"the exported URDF does not load back: {error}") from None
