"""The springs of a URDF written by the URDF export, read back; the export's old import path.

:func:`springs_from_urdf` reads the ``<springbalance:spring>`` records of a URDF written by
:func:`springbalance.export.urdf.export_urdf`, with the anchor points [m] taken from the origins of
the anchor links' joints. The export itself moved to :mod:`springbalance.export.urdf`: its names
still import from here for one release, with a :class:`DeprecationWarning`.
"""

from __future__ import annotations

import json
from pathlib import Path

from springbalance.deprecation import moved_names
from springbalance.errors import InputError
from springbalance.export import urdf
from springbalance.export.common import GROUND
from springbalance.springs.laws import Spring
from springbalance.springs.records import spring_from_dict

__all__ = ["springs_from_urdf"]

_MOVED = ("SIDECAR_FORMAT", "URDF_NAMESPACE", "export_urdf", "sidecar_path", "urdf_strings")


__getattr__ = moved_names(__name__, {name: (urdf, name) for name in _MOVED})


def springs_from_urdf(path: str | Path) -> list[Spring]:
    """The springs recorded in a URDF written by :func:`springbalance.export.urdf.export_urdf`, every value fixed.

    The anchor points are read from the origins of the anchor links' joints, the other
    values from the ``<springbalance:spring>`` records.
    """
    from lxml import etree

    path = Path(path)
    try:
        root = etree.parse(str(path)).getroot()
    except (OSError, etree.XMLSyntaxError) as error:
        raise InputError(f"URDF {str(path)!r} could not be read: {error}") from None
    joints = {joint.find("child").get("link"): joint for joint in root.findall("joint")}
    base = urdf.root_link(root)
    springs = []
    for element in root.iter(f"{{{urdf.URDF_NAMESPACE}}}spring"):
        record = json.loads(element.text)
        routed = record.get("type") == "routed" and isinstance(record.get("path"), list)
        if routed:  # the path's points are the ends a, via1 …, b
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
            body = point["body"] if parent == base and point["body"] == GROUND else parent
            entry = {"body": body, "point": [float(v) for v in origin.get("xyz").split()]}
            if routed:
                record["path"][index] = {**entry, **({"pulley": point["pulley"]} if "pulley" in point else {})}
            else:
                record[end] = entry
        springs.append(spring_from_dict(record, f"{path.name}: spring {record.get('name')!r}"))
    if not springs:
        raise InputError(f"URDF {str(path)!r} holds no springbalance springs")
    return springs
