r"""Export a balanced arm as a URDF with the spring anchors and records.

``export_urdf(result, "balanced.urdf")`` writes

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
the anchor joints' origins.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from springbalance.errors import InputError
from springbalance.files import write_text_atomic
from springbalance.io.export import ExportReport, GROUND, _number, _resolve_package, _source_urdf, _vector, anchor_link_name, law_warnings

URDF_NAMESPACE = "urn:springbalance:urdf-spring:1"
SIDECAR_FORMAT = "springbalance-urdf-springs/1"


def export_urdf(result, path: str | Path, resolve_packages: bool = False, sidecar: bool = True) -> ExportReport:
    """Write the design's URDF with anchor links and spring records; see the module docstring.

    ``resolve_packages``: replace ``package://`` mesh paths by absolute paths (example-robot-data's
    folders, :func:`springbalance.model.robots.package_directories`); by default they are kept.
    ``sidecar``: also write ``<stem>.springs.json`` next to the URDF. Raises
    :class:`~springbalance.errors.InputError` (nothing written) when a name is taken or the
    written file does not read back.
    """
    path = Path(path)
    xml, record = urdf_strings(result, path.name, resolve_packages)
    files = [write_text_atomic(path, xml)]
    if sidecar:
        files.append(write_text_atomic(sidecar_path(path), record))
    return ExportReport(path, files, law_warnings(result))


def urdf_strings(result, name: str = "balanced.urdf", resolve_packages: bool = False) -> tuple[str, str]:
    """(URDF text, sidecar JSON text) of :func:`export_urdf`, checked to load back."""
    from lxml import etree

    text, folder = _source_urdf(result)
    try:
        root = etree.fromstring(text.encode(), parser=etree.XMLParser(remove_blank_text=False))
    except etree.XMLSyntaxError as error:
        raise InputError(f"the design's URDF could not be parsed: {error}") from None
    _rewrite_mesh_paths(root, folder, resolve_packages)
    links = {element.get("name") for element in root.findall("link")}
    joints = {element.get("name") for element in root.findall("joint")}
    root_link = _root_link(root)

    # the namespaced records: the root gets the namespace declaration
    robot = etree.Element("robot", nsmap={"springbalance": URDF_NAMESPACE})
    for key, value in root.attrib.items():
        robot.set(key, value)
    robot.text, robot.tail = root.text, root.tail
    for child in list(root):
        robot.append(child)
    root = robot

    anchor_elements = []
    records = []
    for spring, record, values in zip(result.problem.springs, result.fixed_springs(), result.springs):
        saved = record.to_dict()
        attributes = {"name": spring.name, "type": spring.kind}
        for key in spring.parameter_units:
            attributes[key] = _number(values[key])
        if "joint" in values:
            attributes["joint"] = values["joint"]
        for end in spring.anchors:
            link_name = anchor_link_name(spring.name, end)
            joint_name = link_name + "_joint"
            if link_name in links or joint_name in joints:
                raise InputError(f"cannot add the anchor link {link_name!r}: the URDF already has a link or joint "
                                 f"called {link_name!r} or {joint_name!r}")
            body = values[end]["body"]
            parent = root_link if body == GROUND else body
            anchor_elements += _anchor_elements(link_name, joint_name, parent, values[end]["point"])
            attributes[f"anchor_{end}"] = link_name
            entry = {"body": body, "point": [float(v) for v in values[end]["point"]], "link": link_name}
            if saved.get("type") == "routed":   # the path's points, in order a, via1 …, b
                index = list(spring.anchors).index(end)
                saved["path"][index] = {**entry, **({"pulley": values[end]["pulley"]} if "pulley" in values[end] else {})}
            else:
                saved[end] = entry
        element = etree.SubElement(root, f"{{{URDF_NAMESPACE}}}spring", attrib=attributes)
        element.text = json.dumps(saved)
        records.append(saved)
    for element in anchor_elements:
        root.append(element)
    etree.indent(root, space="  ")
    xml = etree.tostring(root, xml_declaration=True, encoding="utf-8", pretty_print=True).decode()
    _check_urdf(xml, result)
    mechanism = result.problem.mechanism
    sidecar = {"format": SIDECAR_FORMAT, "urdf": name, "namespace": URDF_NAMESPACE,
               "gravity": mechanism.gravity.tolist(), "mimic": bool(mechanism.source.get("mimic", False)),
               "joints": mechanism.joint_names, "springs": records}
    return xml, json.dumps(sidecar, indent=1) + "\n"


def sidecar_path(urdf_path: str | Path) -> Path:
    """``balanced.urdf`` → ``balanced.springs.json``."""
    urdf_path = Path(urdf_path)
    return urdf_path.with_name(urdf_path.stem + ".springs.json")


def _anchor_elements(link_name: str, joint_name: str, parent: str, point) -> list:
    """The massless link and its fixed joint at ``point`` [m] of ``parent``, written by yourdfpy."""
    import yourdfpy
    from lxml import etree

    origin = np.eye(4)
    origin[:3, 3] = np.asarray(point, dtype=float)
    writer = yourdfpy.URDF(robot=yourdfpy.Robot(name="anchor"), build_scene_graph=False, load_meshes=False)
    holder = etree.Element("robot")
    writer._write_link(holder, yourdfpy.Link(name=link_name))
    writer._write_joint(holder, yourdfpy.Joint(name=joint_name, type="fixed", parent=parent, child=link_name,
                                               origin=origin))
    elements = list(holder)
    # yourdfpy writes str(float), which reads back exactly; keep the rpy text plain zeros
    for element in elements:
        for origin_element in element.iter("origin"):
            origin_element.set("xyz", _vector(point))
            origin_element.set("rpy", "0 0 0")
    return elements


def _root_link(root) -> str:
    children = {joint.find("child").get("link") for joint in root.findall("joint") if joint.find("child") is not None}
    roots = [link.get("name") for link in root.findall("link") if link.get("name") not in children]
    if len(roots) != 1:
        raise InputError(f"the URDF has {len(roots)} root links ({', '.join(roots)}); expected one")
    return roots[0]


def _rewrite_mesh_paths(root, folder: Path | None, resolve_packages: bool) -> None:
    from springbalance.model import robots

    for mesh in root.iter("mesh"):
        filename = mesh.get("filename")
        if not filename:
            continue
        if filename.startswith("package://"):
            if resolve_packages:
                resolved = _resolve_package(filename, robots.package_directories())
                if resolved is not None:
                    mesh.set("filename", str(resolved))
        elif filename.startswith("file://"):
            continue
        elif not os.path.isabs(filename) and folder is not None:
            mesh.set("filename", str((folder / filename).resolve()))


def _check_urdf(xml: str, result) -> None:
    """The written URDF loads in Pinocchio and yourdfpy, and its anchors are the design's."""
    import io

    import yourdfpy

    from springbalance.model.mechanism import Mechanism

    try:
        source = result.problem.mechanism.source
        Mechanism.from_urdf_string(xml, mimic=bool(source.get("mimic", False)),
                                   validate=source.get("validate", True) is not False)
        yourdfpy.URDF.load(io.BytesIO(xml.encode()), build_scene_graph=False, load_meshes=False)
    except Exception as error:
        raise InputError(f"the exported URDF does not load back: {error}") from None


def springs_from_urdf(path: str | Path) -> list:
    """The springs recorded in a URDF written by :func:`export_urdf`, every value fixed.

    The anchor points are read from the origins of the anchor links' joints, the other
    values from the ``<springbalance:spring>`` records.
    """
    from lxml import etree

    from springbalance.springs.records import spring_from_dict

    path = Path(path)
    try:
        root = etree.parse(str(path)).getroot()
    except (OSError, etree.XMLSyntaxError) as error:
        raise InputError(f"URDF {str(path)!r} could not be read: {error}") from None
    joints = {joint.find("child").get("link"): joint for joint in root.findall("joint")}
    root_link = _root_link(root)
    springs = []
    for element in root.iter(f"{{{URDF_NAMESPACE}}}spring"):
        record = json.loads(element.text)
        routed = record.get("type") == "routed" and isinstance(record.get("path"), list)
        if routed:   # the path's points are the ends a, via1 …, b
            points = record["path"]
            ends = ["a", *(f"via{i}" for i in range(1, len(points) - 1)), "b"]
        else:
            ends = [end for end in ("a", "b") if end in record]
            points = [record[end] for end in ends]
        for index, (end, point) in enumerate(zip(ends, points)):
            joint = joints.get(element.get(f"anchor_{end}"))
            if joint is None:
                raise InputError(f"URDF {str(path)!r}: spring {record['name']!r} has no anchor link for end {end!r}")
            parent = joint.find("parent").get("link")
            origin = joint.find("origin")
            body = point["body"] if parent == root_link and point["body"] == GROUND else parent
            entry = {"body": body, "point": [float(v) for v in origin.get("xyz").split()]}
            if routed:
                record["path"][index] = {**entry, **({"pulley": point["pulley"]} if "pulley" in point else {})}
            else:
                record[end] = entry
        springs.append(spring_from_dict(record, f"{path.name}: spring {record.get('name')!r}"))
    if not springs:
        raise InputError(f"URDF {str(path)!r} holds no springbalance springs")
    return springs
