"""Design parameters: fixed numbers or free variables with bounds, and spring anchors (the regions an anchor
moves in are :mod:`springbalance.springs.regions`; their names are importable from here too).

A spring parameter is either a number (fixed) or :class:`Free` (a design variable with
bounds and an optional initial guess). A spring end is an :class:`Anchor`: a body name
and a point in that body's frame [m], which is either fixed (a 3-vector), free in a box
(:class:`Free` with 3-vector bounds), free on a segment (:class:`Segment`) or free in a
plane region (:class:`Plane`). Every anchor region is affine in its coordinates,

    p = offset + basis · s,        lower ≤ s ≤ upper,

which is what keeps each spring end affine in the design variables (docs/model.md §2).
"""

from __future__ import annotations

from typing import Any, Sequence, Union

import numpy as np

from springbalance.errors import InputError
from springbalance.springs.regions import Free, Plane, Region, Segment, plane_in_box, vector3

#: What :class:`Anchor` accepts as its point: a fixed 3-vector [m], or a free region.
AnchorPoint = Union[Sequence[float], np.ndarray, Free, Segment, Plane]


#: The world's floor for ``on: floor``: the plane z = 0 of the ``universe`` frame, normal +z.
FLOOR = {"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}


class Anchor:
    """One end of a spring: a point fixed in body ``body`` (URDF link name or ``universe``).

    ``point`` is a fixed 3-vector [m] in the body frame, a :class:`Free` box, a
    :class:`Segment` or a :class:`Plane`.

    ``on`` mounts the anchor on a surface:

    - ``"collision"``: on the surface of the body's own collision geometry, ``offset`` [m] out
      from it (a bracket), within ``point``'s box, or anywhere around the geometry when no box
      is given (its bounding box grown by ``offset`` + 5 mm). The surface comes from the URDF, so
      the design problem resolves it (:mod:`springbalance.design.clearance`).
    - ``"floor"`` or a plane ``{"point": [..], "normal": [..]}`` (body frame; for ``universe``
      the world): the anchor is free on that plane inside ``point``'s box. The region becomes a
      :class:`Plane` at once: for a plane normal to a box axis it is exactly the box's face
      through the plane; otherwise the rectangle (in the plane) that bounds the box's section.
    """

    def __init__(
        self, body: str, point: AnchorPoint | None = (0.0, 0.0, 0.0), on: str | dict | None = None, offset: float = 0.0
    ) -> None:
        if not isinstance(body, str) or not body:
            raise InputError(f"anchor body must be a link name, got {body!r}")
        self.body = body
        self.mount: str | dict[str, Any] | None = None
        self.offset = 0.0
        if on is not None:
            point = self._mount(on, point, offset)
        elif point is None:
            raise InputError(f"anchor on {body!r}: give a point, box, segment or plane")
        self.point = point
        if point is None:  # on collision without a box: the design problem sets the region
            return
        if isinstance(point, Free):
            if point.lower.shape != (3,):
                raise InputError(f"anchor on {body!r}: a Free point needs 3-vector bounds, got {point.lower.tolist()}")
        elif not isinstance(point, (Segment, Plane)):
            self.point = vector3(point, f"anchor point on {body!r}")

    def _mount(self, on: str | dict, point: AnchorPoint | None, offset: float) -> AnchorPoint | None:
        """Check a mounting (``on``, ``offset``) and return the anchor's point or region."""
        where = f"anchor on {self.body!r}"
        if isinstance(offset, bool) or not isinstance(offset, (int, float)) or not np.isfinite(offset) or offset < 0:
            raise InputError(f"{where}: offset must be a finite number ≥ 0 [m], got {offset!r}")
        if on == "collision":
            if point is not None and not isinstance(point, Free):
                raise InputError(f"{where}: 'on: collision' takes a box (or nothing), not a {type(point).__name__}")
            self.mount, self.offset = "collision", float(offset)
            return point
        if offset:
            raise InputError(f"{where}: offset applies to 'on: collision' only")
        plane = FLOOR if on == "floor" else on
        if not isinstance(plane, dict) or set(plane) != {"point", "normal"}:
            raise InputError(f"{where}: 'on' must be 'collision', 'floor' or a plane {{point, normal}}, got {on!r}")
        if not isinstance(point, Free):
            raise InputError(
                f"{where}: 'on: {on if isinstance(on, str) else 'plane'}' needs a box that bounds where "
                "on the plane the anchor may go"
            )
        self.mount = (
            "floor"
            if on == "floor"
            else {
                "point": vector3(plane["point"], f"{where}: plane point").tolist(),
                "normal": vector3(plane["normal"], f"{where}: plane normal").tolist(),
            }
        )
        return plane_in_box(
            vector3(plane["point"], f"{where}: plane point"),
            vector3(plane["normal"], f"{where}: plane normal"),
            point,
            where,
        )

    @property
    def is_free(self) -> bool:
        """True when the anchor has design coordinates (a box with some free axis, a segment, a plane)."""
        return self.region().basis.shape[1] > 0

    def region(self) -> Region:
        """The affine region; components of a box with equal bounds are folded into the offset."""
        point = self.point
        if point is None:
            raise InputError(
                f"anchor on {self.body!r} mounted 'on: collision' has no region yet; "
                "a DesignProblem sets it from the body's collision geometry"
            )
        if isinstance(point, (Segment, Plane)):
            return point.region()
        if isinstance(point, Free):
            free_axes = [i for i in range(3) if point.upper[i] > point.lower[i]]
            offset = np.where(point.upper > point.lower, 0.0, point.lower)
            basis = np.eye(3)[:, free_axes]
            return Region(
                offset,
                basis,
                point.lower[free_axes],
                point.upper[free_axes],
                point.start[free_axes],
                tuple("xyz"[i] for i in free_axes),
            )
        return Region(np.asarray(point, dtype=float), np.zeros((3, 0)), np.zeros(0), np.zeros(0), np.zeros(0), ())

    def to_dict(self) -> dict[str, Any]:
        """``{body, point | box | segment | plane, on?, offset?}`` (the config form)."""
        point = self.point
        if self.mount is not None:
            record: dict[str, Any] = {"body": self.body, "on": self.mount}
            if self.mount == "collision" and self.offset:
                record["offset"] = self.offset
            if isinstance(point, Free):
                record["box"] = point.to_dict()
            elif isinstance(point, Plane):
                record["box"] = self.mount_box.to_dict()
            return record
        if isinstance(point, Free):
            return {"body": self.body, "box": point.to_dict()}
        if isinstance(point, (Segment, Plane)):
            return {"body": self.body, **point.to_dict()}
        return {"body": self.body, "point": np.asarray(point, dtype=float).tolist()}

    @property
    def mount_box(self) -> Free:
        """The box a plane mounting was cut from."""
        point = self.point
        assert isinstance(point, Plane)  # only a plane mounting has a box
        return point.box

    def __repr__(self) -> str:
        return f"Anchor({self.body!r}, {self.point!r}{'' if self.mount is None else f', on={self.mount!r}'})"


def check_keys(record: Any, valid: Sequence[str], where: str) -> dict[str, Any]:
    """Reject a mapping with keys outside ``valid``; the message lists the valid ones."""
    if not isinstance(record, dict):
        raise InputError(f"{where}: expected a mapping, got {type(record).__name__} {record!r}")
    unknown = [key for key in record if key not in valid]
    if unknown:
        raise InputError(f"{where}: unknown key {unknown[0]!r}; valid keys: {', '.join(valid)}")
    return record


def free_from_dict(record: Any, where: str) -> Free:
    """``{lower, upper, init?}`` → :class:`Free`."""
    check_keys(record, ("lower", "upper", "init"), where)
    for key in ("lower", "upper"):
        if key not in record:
            raise InputError(f"{where}: missing key {key!r}")
    try:
        return Free(record["lower"], record["upper"], record.get("init"))
    except InputError as error:
        raise InputError(f"{where}: {error}") from None
    except (TypeError, ValueError):
        raise InputError(f"{where}: bounds must be numbers, got {record!r}") from None


def value_from_record(value: Any, where: str) -> float | Free:
    """A number, or a ``{lower, upper, init?}`` mapping for a free variable."""
    if isinstance(value, dict):
        return free_from_dict(value, where)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{where}: expected a number or {{lower, upper}}, got {value!r}")
    return float(value)


def anchor_from_dict(record: Any, where: str) -> Anchor:
    """``{body, point | box | segment | plane, on?, offset?}`` → :class:`Anchor`."""
    check_keys(record, ("body", "point", "box", "segment", "plane", "on", "offset"), where)
    if "body" not in record:
        raise InputError(f"{where}: missing key 'body'")
    kinds = [key for key in ("point", "box", "segment", "plane") if key in record]
    if len(kinds) > 1:
        raise InputError(f"{where}: give one of point, box, segment, plane (got {', '.join(kinds)})")
    if "offset" in record and "on" not in record:
        raise InputError(f"{where}: 'offset' needs 'on: collision'")
    kind = kinds[0] if kinds else "point"
    spec = record.get(kind, [0.0, 0.0, 0.0])
    try:
        if "on" in record:
            if kind not in ("box",) and kinds:
                raise InputError(f"'on: ...' takes a box (or nothing), not a {kind}")
            box = free_from_dict(spec, f"{where}.box") if kinds else None
            return Anchor(record["body"], box, on=record["on"], offset=record.get("offset", 0.0))
        if kind == "point":
            return Anchor(record["body"], spec)
        if kind == "box":
            return Anchor(record["body"], free_from_dict(spec, f"{where}.box"))
        if kind == "segment":
            check_keys(spec, ("start", "end", "lower", "upper", "init"), f"{where}.segment")
            return Anchor(
                record["body"],
                Segment(
                    spec.get("start"), spec.get("end"), spec.get("init"), spec.get("lower", 0.0), spec.get("upper", 1.0)
                ),
            )
        check_keys(spec, ("origin", "u", "v", "lower", "upper", "init"), f"{where}.plane")
        return Anchor(
            record["body"],
            Plane(
                spec.get("origin"), spec.get("u"), spec.get("v"), spec.get("lower"), spec.get("upper"), spec.get("init")
            ),
        )
    except InputError as error:
        if str(error).startswith(where):
            raise
        raise InputError(f"{where}: {error}") from None


class Pulley:
    """A point of a routed spring's path after its first end: a pulley of ``radius`` [m] (0: a
    guide point or eyelet the cable passes through) on ``anchor`` (an :class:`Anchor`: a fixed
    point, or free in a region like any anchor). The last point of a path is where the cable ends."""

    def __init__(self, anchor: Anchor, radius: float = 0.0) -> None:
        if not isinstance(anchor, Anchor):
            raise InputError(f"a pulley sits on an Anchor, got {anchor!r}")
        if (
            isinstance(radius, bool)
            or not isinstance(radius, (int, float, np.floating))
            or not np.isfinite(radius)
            or radius < 0
        ):
            raise InputError(f"pulley on {anchor.body!r}: radius must be a finite number ≥ 0 [m], got {radius!r}")
        self.anchor, self.radius = anchor, float(radius)

    def to_dict(self) -> dict[str, Any]:
        """The anchor's record, with ``pulley: {radius}`` for a wrapping pulley."""
        record = self.anchor.to_dict()
        if self.radius > 0:
            record["pulley"] = {"radius": self.radius}
        return record

    def __repr__(self) -> str:
        return f"Pulley({self.anchor!r}, radius={self.radius:g})"


def path_from_dict(records: Any, where: str) -> list[tuple[Anchor, float]]:
    """``[{body, point | box | ..., pulley?: {radius}}, ...]`` → ``[(anchor, radius), ...]`` (≥ 2 points)."""
    if not isinstance(records, list) or len(records) < 2:
        raise InputError(
            f"{where}: a path needs at least two points (the spring's end, then the cable's end), got {records!r}"
        )
    path = []
    for i, record in enumerate(records):
        here = f"{where}[{i}]"
        if not isinstance(record, dict):
            raise InputError(f"{here}: expected a mapping {{body, point | box, pulley?}}, got {record!r}")
        radius = 0.0
        if "pulley" in record:
            if i in (0, len(records) - 1):
                raise InputError(
                    f"{here}.pulley: the first and last points are the path's ends; only the points "
                    "between them carry pulleys"
                )
            pulley = check_keys(record["pulley"], ("radius",), f"{here}.pulley")
            radius = pulley.get("radius", 0.0)
            if (
                isinstance(radius, bool)
                or not isinstance(radius, (int, float))
                or not np.isfinite(radius)
                or radius < 0
            ):
                raise InputError(f"{here}.pulley.radius: must be a finite number ≥ 0 [m], got {radius!r}")
        anchor = anchor_from_dict({key: value for key, value in record.items() if key != "pulley"}, here)
        path.append((anchor, float(radius)))
    return path
