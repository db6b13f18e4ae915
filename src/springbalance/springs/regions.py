"""Anchor regions: free variables with bounds (:class:`Free`) and the regions an anchor point may move in.

Every region is affine in its coordinates, ``p = offset + basis · s`` with ``lower ≤ s ≤ upper``
(:class:`Region`): a box (:class:`Free` with 3-vector bounds), a segment (:class:`Segment`) or a plane
region (:class:`Plane`). This is what keeps each spring end affine in the design variables
(docs/model.md §2). Units: [m].
"""

from __future__ import annotations

import dataclasses
from typing import Any, Sequence

import numpy as np
import numpy.typing as npt

from springbalance.errors import InputError


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
            raise InputError(
                f"Free bounds must be numbers (or equal-length lists of numbers), got lower {lower!r}, "
                f"upper {upper!r}" + ("" if init is None else f", init {init!r}")
            ) from None
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
                raise InputError(
                    f"Free init {self.init.tolist()!r} lies outside [{self.lower.tolist()}, {self.upper.tolist()}]"
                )

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

    offset: np.ndarray  # (3,)
    basis: np.ndarray  # (3, m)
    lower: np.ndarray  # (m,)
    upper: np.ndarray  # (m,)
    start: np.ndarray  # (m,)
    labels: tuple[str, ...]

    def point(self, coordinates: npt.ArrayLike) -> np.ndarray:
        """The point ``offset + basis · coordinates`` [m]."""
        return self.offset + self.basis @ np.asarray(coordinates, dtype=float)


class Segment:
    """Anchor free on the segment from ``start`` to ``end`` (body frame, m).

    The design coordinate is the fraction ``s ∈ [lower, upper] ⊆ [0, 1]`` along it.
    """

    def __init__(
        self,
        start: Sequence[float],
        end: Sequence[float],
        init: float | None = None,
        lower: float = 0.0,
        upper: float = 1.0,
    ) -> None:
        self.start = vector3(start, "Segment start")
        self.end = vector3(end, "Segment end")
        if np.allclose(self.start, self.end):
            raise InputError(f"Segment from {self.start.tolist()} to {self.end.tolist()} has zero length")
        self.bounds = Free(lower, upper, init)

    def region(self) -> Region:
        """The affine region: one coordinate, the fraction ``s`` along the segment."""
        return Region(
            self.start,
            (self.end - self.start)[:, None],
            np.atleast_1d(self.bounds.lower),
            np.atleast_1d(self.bounds.upper),
            np.atleast_1d(self.bounds.start),
            ("s",),
        )

    def to_dict(self) -> dict[str, Any]:
        """``{"segment": {start, end, lower, upper, init?}}`` (the config form)."""
        return {"segment": {"start": self.start.tolist(), "end": self.end.tolist(), **free_fields(self.bounds)}}


class Plane:
    """Anchor free in a rectangle of a plane: ``p = origin + s·u + t·v`` with bounded ``(s, t)``.

    ``u`` and ``v`` are body-frame directions (normalised here); bounds are in metres
    along them.
    """

    #: the box a plane mounting was cut from (set by :func:`plane_in_box` only)
    box: Free

    def __init__(
        self,
        origin: npt.ArrayLike,
        u: npt.ArrayLike,
        v: npt.ArrayLike,
        lower: npt.ArrayLike,
        upper: npt.ArrayLike,
        init: npt.ArrayLike | None = None,
    ) -> None:
        self.origin = vector3(origin, "Plane origin")
        u_dir, v_dir = vector3(u, "Plane u"), vector3(v, "Plane v")
        if np.linalg.norm(np.cross(u_dir, v_dir)) < 1e-12 * max(np.linalg.norm(u_dir) * np.linalg.norm(v_dir), 1e-300):
            raise InputError(f"Plane directions u={u_dir.tolist()} and v={v_dir.tolist()} are parallel or zero")
        self.u, self.v = u_dir / np.linalg.norm(u_dir), v_dir / np.linalg.norm(v_dir)
        self.bounds = Free(lower, upper, init)
        if self.bounds.lower.shape != (2,):
            raise InputError(f"Plane bounds must have two entries (along u and v), got {lower!r}")

    def region(self) -> Region:
        """The affine region: two coordinates [m] along ``u`` and ``v``."""
        return Region(
            self.origin,
            np.column_stack([self.u, self.v]),
            self.bounds.lower,
            self.bounds.upper,
            self.bounds.start,
            ("u", "v"),
        )

    def to_dict(self) -> dict[str, Any]:
        """``{"plane": {origin, u, v, lower, upper, init?}}`` (the config form)."""
        return {
            "plane": {
                "origin": self.origin.tolist(),
                "u": self.u.tolist(),
                "v": self.v.tolist(),
                **free_fields(self.bounds),
            }
        }


def plane_in_box(origin: np.ndarray, normal: np.ndarray, box: Free, where: str) -> Plane:
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
        raise InputError(
            f"{where}: the mounting plane (point {origin.tolist()}, normal {normal.tolist()}) does not "
            f"cross the box {box.lower.tolist()}..{box.upper.tolist()}: no anchor can reach it"
        )
    axis = int(np.argmax(np.abs(normal)))
    u = np.eye(3)[(axis + 1) % 3]
    u = u - (u @ normal) * normal
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    points = []  # where the plane cuts the box's 12 edges (and the corners on it)
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


def vector3(value: npt.ArrayLike, label: str) -> np.ndarray:
    try:
        vector = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{label} must be three numbers, got {value!r}") from None
    if vector.shape != (3,):
        raise InputError(f"{label} must be three numbers, got {value!r}")
    if not np.all(np.isfinite(vector)):
        raise InputError(f"{label} must be finite, got {vector.tolist()!r}")
    return vector


def free_fields(free: Free) -> dict[str, Any]:
    record = {"lower": free.lower.tolist(), "upper": free.upper.tolist()}
    if free.init is not None:
        record["init"] = free.init.tolist()
    return record


# ---------------------------------------------------------------------- records → objects
