"""Design parameters: fixed numbers or free variables with bounds, and spring anchors.

A spring parameter is either a number (fixed) or :class:`Free` (a design variable with
bounds and an optional initial guess). A spring end is an :class:`Anchor`: a body name
and a point in that body's frame [m], which is either fixed (a 3-vector), free in a box
(:class:`Free` with 3-vector bounds), free on a segment (:class:`Segment`) or free in a
plane region (:class:`Plane`). Every anchor region is affine in its coordinates,

    p = offset + basis · s,        lower ≤ s ≤ upper,

which is what keeps each spring end affine in the design variables (docs/model.md §2).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Sequence, Union

import numpy as np
import numpy.typing as npt

from springbalance.errors import InputError

#: What :class:`Anchor` accepts as its point: a fixed 3-vector [m], or a free region.
AnchorPoint = Union[Sequence[float], np.ndarray, "Free", "Segment", "Plane"]


class Free:
    """A design variable: ``lower ≤ value ≤ upper``, scalar or vector.

    ``Free(0, 1e4)`` is a scalar; ``Free(lower=[0.05, 0, 0], upper=[0.5, 0, 0])`` is a
    box for an anchor point, where components with equal bounds stay fixed. ``init`` is
    the first start of the multi-start (default: the middle of the bounds).
    """

    def __init__(self, lower: npt.ArrayLike, upper: npt.ArrayLike, init: npt.ArrayLike | None = None) -> None:
        try:
            self.lower = np.asarray(lower, dtype=float)
            self.upper = np.asarray(upper, dtype=float)
            self.init = None if init is None else np.asarray(init, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"Free bounds must be numbers (or equal-length lists of numbers), got lower {lower!r}, "
                             f"upper {upper!r}" + ("" if init is None else f", init {init!r}")) from None
        if self.lower.shape != self.upper.shape:
            raise InputError(f"Free bounds have different shapes: lower {lower!r}, upper {upper!r}")
        checked: list[tuple[str, np.ndarray]] = [("lower", self.lower), ("upper", self.upper)]
        if self.init is not None:
            checked.append(("init", self.init))
        for label, value in checked:
            if not np.all(np.isfinite(value)):
                raise InputError(f"Free {label} bound must be finite, got {value.tolist()!r}")
        if np.any(self.lower > self.upper):
            raise InputError(f"Free bounds: lower {self.lower.tolist()!r} > upper {self.upper.tolist()!r}")
        if self.init is not None:
            if self.init.shape != self.lower.shape:
                raise InputError(f"Free init {init!r} does not match the bounds' shape {self.lower.shape}")
            if np.any(self.init < self.lower) or np.any(self.init > self.upper):
                raise InputError(f"Free init {self.init.tolist()!r} lies outside [{self.lower.tolist()}, {self.upper.tolist()}]")

    @property
    def start(self) -> np.ndarray:
        """Initial guess: ``init`` or the middle of the bounds."""
        return self.init if self.init is not None else (self.lower + self.upper) / 2

    def to_dict(self) -> dict[str, Any]:
        """``{lower, upper, init?}`` as plain lists/numbers (the config form)."""
        record = {"lower": self.lower.tolist(), "upper": self.upper.tolist()}
        if self.init is not None:
            record["init"] = self.init.tolist()
        return record

    def __repr__(self) -> str:
        return f"Free({self.lower.tolist()}, {self.upper.tolist()})"


@dataclasses.dataclass(frozen=True)
class Region:
    """Affine anchor region ``p = offset + basis · s`` with ``lower ≤ s ≤ upper`` [m]."""

    offset: np.ndarray      # (3,)
    basis: np.ndarray       # (3, m)
    lower: np.ndarray       # (m,)
    upper: np.ndarray       # (m,)
    start: np.ndarray       # (m,)
    labels: tuple[str, ...]

    def point(self, coordinates: npt.ArrayLike) -> np.ndarray:
        """The point ``offset + basis · coordinates`` [m]."""
        return self.offset + self.basis @ np.asarray(coordinates, dtype=float)


class Segment:
    """Anchor free on the segment from ``start`` to ``end`` (body frame, m).

    The design coordinate is the fraction ``s ∈ [lower, upper] ⊆ [0, 1]`` along it.
    """

    def __init__(self, start: Sequence[float], end: Sequence[float], init: float | None = None,
                 lower: float = 0.0, upper: float = 1.0) -> None:
        self.start = _vector3(start, "Segment start")
        self.end = _vector3(end, "Segment end")
        if np.allclose(self.start, self.end):
            raise InputError(f"Segment from {self.start.tolist()} to {self.end.tolist()} has zero length")
        self.bounds = Free(lower, upper, init)

    def region(self) -> Region:
        """The affine region: one coordinate, the fraction ``s`` along the segment."""
        return Region(self.start, (self.end - self.start)[:, None], np.atleast_1d(self.bounds.lower),
                      np.atleast_1d(self.bounds.upper), np.atleast_1d(self.bounds.start), ("s",))

    def to_dict(self) -> dict[str, Any]:
        """``{"segment": {start, end, lower, upper, init?}}`` (the config form)."""
        return {"segment": {"start": self.start.tolist(), "end": self.end.tolist(), **_free_fields(self.bounds)}}


class Plane:
    """Anchor free in a rectangle of a plane: ``p = origin + s·u + t·v`` with bounded ``(s, t)``.

    ``u`` and ``v`` are body-frame directions (normalised here); bounds are in metres
    along them.
    """

    #: the box a plane mounting was cut from (set by :func:`_plane_in_box` only)
    box: Free

    def __init__(self, origin: npt.ArrayLike, u: npt.ArrayLike, v: npt.ArrayLike,
                 lower: npt.ArrayLike, upper: npt.ArrayLike, init: npt.ArrayLike | None = None) -> None:
        self.origin = _vector3(origin, "Plane origin")
        u_dir, v_dir = _vector3(u, "Plane u"), _vector3(v, "Plane v")
        if np.linalg.norm(np.cross(u_dir, v_dir)) < 1e-12 * max(np.linalg.norm(u_dir) * np.linalg.norm(v_dir), 1e-300):
            raise InputError(f"Plane directions u={u_dir.tolist()} and v={v_dir.tolist()} are parallel or zero")
        self.u, self.v = u_dir / np.linalg.norm(u_dir), v_dir / np.linalg.norm(v_dir)
        self.bounds = Free(lower, upper, init)
        if self.bounds.lower.shape != (2,):
            raise InputError(f"Plane bounds must have two entries (along u and v), got {lower!r}")

    def region(self) -> Region:
        """The affine region: two coordinates [m] along ``u`` and ``v``."""
        return Region(self.origin, np.column_stack([self.u, self.v]), self.bounds.lower, self.bounds.upper,
                      self.bounds.start, ("u", "v"))

    def to_dict(self) -> dict[str, Any]:
        """``{"plane": {origin, u, v, lower, upper, init?}}`` (the config form)."""
        return {"plane": {"origin": self.origin.tolist(), "u": self.u.tolist(), "v": self.v.tolist(),
                          **_free_fields(self.bounds)}}


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

    def __init__(self, body: str, point: AnchorPoint | None = (0.0, 0.0, 0.0), on: str | dict | None = None,
                 offset: float = 0.0) -> None:
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
            self.point = _vector3(point, f"anchor point on {body!r}")

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
            raise InputError(f"{where}: 'on: {on if isinstance(on, str) else 'plane'}' needs a box that bounds where "
                             "on the plane the anchor may go")
        self.mount = "floor" if on == "floor" else {"point": _vector3(plane["point"], f"{where}: plane point").tolist(),
                                                    "normal": _vector3(plane["normal"], f"{where}: plane normal").tolist()}
        return _plane_in_box(_vector3(plane["point"], f"{where}: plane point"),
                             _vector3(plane["normal"], f"{where}: plane normal"), point, where)

    @property
    def is_free(self) -> bool:
        """True when the anchor has design coordinates (a box with some free axis, a segment, a plane)."""
        return self.region().basis.shape[1] > 0

    def region(self) -> Region:
        """The affine region; components of a box with equal bounds are folded into the offset."""
        point = self.point
        if point is None:
            raise InputError(f"anchor on {self.body!r} mounted 'on: collision' has no region yet; "
                             "a DesignProblem sets it from the body's collision geometry")
        if isinstance(point, (Segment, Plane)):
            return point.region()
        if isinstance(point, Free):
            free_axes = [i for i in range(3) if point.upper[i] > point.lower[i]]
            offset = np.where(point.upper > point.lower, 0.0, point.lower)
            basis = np.eye(3)[:, free_axes]
            return Region(offset, basis, point.lower[free_axes], point.upper[free_axes], point.start[free_axes],
                          tuple("xyz"[i] for i in free_axes))
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


def _plane_in_box(origin: np.ndarray, normal: np.ndarray, box: Free, where: str) -> Plane:
    """The part of the plane through ``origin`` with ``normal`` inside ``box``, as a :class:`Plane` region.

    Exact for a normal along a box axis; otherwise the bounding rectangle (in the plane) of the
    polygon where the plane cuts the box. Raises :class:`InputError` when the plane misses the box.
    """
    if box.lower.shape != (3,):
        raise InputError(f"{where}: a mounting plane needs a 3-vector box, got {box.lower.tolist()}")
    norm = float(np.linalg.norm(normal))
    if norm < 1e-12:
        raise InputError(f"{where}: the mounting plane's normal is zero")
    normal = normal / norm
    corners = np.array([[box.lower[i] if (k >> i) & 1 == 0 else box.upper[i] for i in range(3)] for k in range(8)])
    side = (corners - origin) @ normal
    if side.min() > 1e-12 or side.max() < -1e-12:
        raise InputError(f"{where}: the mounting plane (point {origin.tolist()}, normal {normal.tolist()}) does not "
                         f"cross the box {box.lower.tolist()}..{box.upper.tolist()}: no anchor can reach it")
    axis = int(np.argmax(np.abs(normal)))
    u = np.eye(3)[(axis + 1) % 3]
    u = u - (u @ normal) * normal
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    points = []   # where the plane cuts the box's 12 edges (and the corners on it)
    for a in range(8):
        for b in range(a + 1, 8):
            if bin(a ^ b).count("1") != 1:
                continue
            if side[a] == side[b] == 0 or side[a] * side[b] <= 0:
                t = 0.0 if side[a] == side[b] else side[a] / (side[a] - side[b])
                points.append(corners[a] + t * (corners[b] - corners[a]))
    centre = origin + ((np.mean(points, axis=0) - origin) @ u) * u + ((np.mean(points, axis=0) - origin) @ v) * v
    local = np.array([[(p - centre) @ u, (p - centre) @ v] for p in points])
    plane = Plane(centre, u, v, local.min(axis=0), local.max(axis=0))
    plane.box = box
    return plane


def _vector3(value: npt.ArrayLike, label: str) -> np.ndarray:
    try:
        vector = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{label} must be three numbers, got {value!r}") from None
    if vector.shape != (3,):
        raise InputError(f"{label} must be three numbers, got {value!r}")
    if not np.all(np.isfinite(vector)):
        raise InputError(f"{label} must be finite, got {vector.tolist()!r}")
    return vector


def _free_fields(free: Free) -> dict[str, Any]:
    record = {"lower": free.lower.tolist(), "upper": free.upper.tolist()}
    if free.init is not None:
        record["init"] = free.init.tolist()
    return record


# ---------------------------------------------------------------------- records → objects
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
            return Anchor(record["body"], Segment(spec.get("start"), spec.get("end"), spec.get("init"),
                                                  spec.get("lower", 0.0), spec.get("upper", 1.0)))
        check_keys(spec, ("origin", "u", "v", "lower", "upper", "init"), f"{where}.plane")
        return Anchor(record["body"], Plane(spec.get("origin"), spec.get("u"), spec.get("v"), spec.get("lower"),
                                            spec.get("upper"), spec.get("init")))
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
        if isinstance(radius, bool) or not isinstance(radius, (int, float, np.floating)) or not np.isfinite(radius) \
                or radius < 0:
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
        raise InputError(f"{where}: a path needs at least two points (the spring's end, then the cable's end), "
                         f"got {records!r}")
    path = []
    for i, record in enumerate(records):
        here = f"{where}[{i}]"
        if not isinstance(record, dict):
            raise InputError(f"{here}: expected a mapping {{body, point | box, pulley?}}, got {record!r}")
        radius = 0.0
        if "pulley" in record:
            if i in (0, len(records) - 1):
                raise InputError(f"{here}.pulley: the first and last points are the path's ends; only the points "
                                 "between them carry pulleys")
            pulley = check_keys(record["pulley"], ("radius",), f"{here}.pulley")
            radius = pulley.get("radius", 0.0)
            if isinstance(radius, bool) or not isinstance(radius, (int, float)) or not np.isfinite(radius) or radius < 0:
                raise InputError(f"{here}.pulley.radius: must be a finite number ≥ 0 [m], got {radius!r}")
        anchor = anchor_from_dict({key: value for key, value in record.items() if key != "pulley"}, here)
        path.append((anchor, float(radius)))
    return path
