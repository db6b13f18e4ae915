r"""Springs that fit the arm: clearance from its links, and anchors mounted on its surfaces.

**Clearance.** A two-point spring is a capsule of radius ``r`` [m] (half the outer diameter of
its coil, or :attr:`Clearance.radius`) around the segment between its world end points
``E_a(x), E_b(x)``; it must keep ``margin`` from every collision object of the arm except those
of its own two anchor bodies, at every pose (:mod:`springbalance.model.collision`). Meshes count
as their convex hulls, which contain them.

For a fixed pose the ends are affine in the anchor coordinates (docs/model.md §2), and the
distance to a convex object is linearised by a **separating plane**: coal gives the witness
point ``w`` on the object and the unit normal ``n`` towards the capsule, and both ends must stay
on the far side of the plane through ``w``,

.. math:: n^\top (E_e(x) - w) - r - m^+ \ge 0, \qquad e \in \{a, b\},

two rows affine in ``x`` (:class:`~springbalance.design.problem.LinearRows`). Keeping both ends
beyond the plane keeps the whole segment beyond it, so the rows are *sufficient* for the margin at
that pose, and at the design where they are built they hold exactly when the distance is at
least ``m^+`` (the closest point of the segment has the smallest ``n``-coordinate). ``m^+`` is
the margin plus a buffer (:attr:`Clearance.buffer`) for the poses between the ones checked.

Two springs (``between_springs``) are kept apart by the plane halfway between their witness
points: each end of one spring on its side by ``r_i + m^+/2``.

**The loop** (:func:`fit_to_arm`): from the multi-start's optimum, check every spring against
every object at ``check_samples`` poses (scrambled Sobol, seed 0, over the workspace's joint
ranges). Each pose where a spring comes closer than the margin joins the watched set; the rows
of every watched pose are rebuilt at the current design and the problem is solved again from
it (one warm start). When the check set is clear, a 4× denser set (seed 1) is checked too, and
its violations join the watched set. When both are clear, a bounded descent over the joint
coordinates from the closest sampled poses of every pair that comes near searches for the
closest approach between the samples (in six joints, even thousands of samples lie far apart),
and the minima below the margin join the watched set and are checked in every later round.
The loop ends when all three are clear, or after
:attr:`Clearance.rounds` rounds; its record (:class:`FitRecord`) says which, and what the
clearance cost (the objective before and after). When it does not converge, it runs once more from the
same design with each round inside a trust region first
(:func:`~springbalance.design.clearance_round.trust_rows`).

**Mounting.** An anchor ``on: collision`` lies ``offset`` [m] outside its body's collision
surface (the union of the body's objects; meshes as hulls). In the body frame this does not
depend on the pose: with ``w`` the closest surface point and ``n`` the outward normal at the
current anchor point ``p``, the row ``n^\top (p(x) - w) - \text{offset} + t \ge 0`` (``t`` = 0.2 mm)
holds it on the far side of the offset tangent plane, and ``\text{offset} - n^\top (p(x) - w) + t \ge 0``,
kept for every tangent plane met so far, inside the (convex) offset body: each such plane bounds
that body, so none cuts off a point of its surface. Together they hold the anchor on the surface;
they are rebuilt every round until ``p`` is within 0.5 mm of it. Floor and wall mountings need no loop: they are plane regions
(:class:`~springbalance.springs.params.Anchor`).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from springbalance.design.objectives import percent_change
from springbalance.errors import InputError

#: most re-solves of a fitting loop (:attr:`Clearance.rounds`; also the mountings' without a clearance)
FIT_ROUNDS = 24


@dataclasses.dataclass(frozen=True)
class Clearance:
    """What clearance the springs must keep from the arm (see the module documentation).

    Attributes:
        margin: smallest distance [m] between a spring's capsule and any link it is not attached to.
        check_samples: poses checked by the loop (a 4× denser set is checked at the end).
        radius: capsule radius [m] of springs without a helical spec sheet (default 0.01 m).
        between_springs: keep the springs ``margin`` from each other too.
        buffer: extra distance [m] the rows ask for, for the poses between the checked ones
            (default: 10 % of the margin, at least 0.5 mm).
        rounds: most re-solves of the loop.
        starts: how many of the multi-start's best feasible designs the loop fits (each from its own
            start); the fitted design of lowest objective is kept. The loop linearises around the
            design it starts from, so a second or third start can end in a better optimum.
    """

    margin: float = 0.005
    check_samples: int = 1024
    radius: float | None = None
    between_springs: bool = False
    buffer: float | None = None
    rounds: int = FIT_ROUNDS
    starts: int = 1

    def __post_init__(self) -> None:
        for key in ("margin", "buffer"):
            value = getattr(self, key)
            if value is None and key == "buffer":
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) or value < 0:
                raise InputError(f"clearance.{key} must be a finite number ≥ 0 [m], got {value!r}")
        if self.radius is not None and (
            isinstance(self.radius, bool)
            or not isinstance(self.radius, (int, float))
            or not np.isfinite(self.radius)
            or self.radius <= 0
        ):
            raise InputError(f"clearance.radius must be a finite number > 0 [m], got {self.radius!r}")
        for key in ("check_samples", "rounds", "starts"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
                raise InputError(f"clearance.{key} must be an integer ≥ 1, got {value!r}")

    @property
    def target(self) -> float:
        """The distance [m] the rows ask for: margin + buffer."""
        buffer = max(0.1 * self.margin, 5e-4) if self.buffer is None else self.buffer
        return self.margin + buffer

    def to_dict(self) -> dict[str, Any]:
        return {key: value for key, value in dataclasses.asdict(self).items() if value is not None}

    @classmethod
    def from_dict(cls, record: Any, where: str = "clearance") -> Clearance:
        if not isinstance(record, dict):
            raise InputError(f"{where}: expected a mapping {{margin, check_samples, ...}}, got {record!r}")
        valid = [field.name for field in dataclasses.fields(cls)]
        unknown = [key for key in record if key not in valid]
        if unknown:
            raise InputError(f"{where}: unknown key {unknown[0]!r}; valid keys: {', '.join(valid)}")
        return cls(**record)


@dataclasses.dataclass
class FitRecord:
    """What fitting the springs to the arm did and cost.

    Attributes:
        rounds: re-solves made.
        rows: linearised rows in the last solve.
        converged: the last check found no spring below the margin and every mounted anchor on its
            surface.
        objective_before: the objective of the multi-start's optimum (no clearance, no mounting).
        objective: the objective of the fitted design.
        closest: spring name → smallest distance [m] to the arm (or another spring) over the
            poses checked in the last round (check set and dense set).
        mounts: ``"<spring>.<end>"`` → distance [m] of a mounted anchor from its offset surface.
        poses: the number of poses checked (check set + dense set).
        seconds: wall time of the loop (of every fitted start).
        starts: how many of the multi-start's designs were fitted (the best fit is this record's).
    """

    @property
    def rounds_text(self) -> str:
        """``"N round(s)"``, or ``"N round(s) over S starts"`` when several designs were fitted (``rounds``
        then counts the rounds of all of them)."""
        return f"{self.rounds} round(s)" + (f" over {self.starts} starts" if self.starts > 1 else "")

    rounds: int
    rows: int
    converged: bool
    objective_before: float
    objective: float
    closest: dict = dataclasses.field(default_factory=dict)
    mounts: dict = dataclasses.field(default_factory=dict)
    poses: int = 0
    seconds: float = 0.0
    starts: int = 1

    @property
    def cost_percent(self) -> float:
        """How much worse the objective got [%]."""
        return percent_change(self.objective_before, self.objective)

    def to_dict(self) -> dict[str, Any]:
        return {**dataclasses.asdict(self), "cost_percent": self.cost_percent}

    @classmethod
    def from_dict(cls, record: Any) -> FitRecord | None:
        """The record a saved design carries (None when it has none or it is damaged)."""
        if not isinstance(record, dict):
            return None
        try:
            return cls(**{field.name: record[field.name] for field in dataclasses.fields(cls) if field.name in record})
        except TypeError:
            return None


@dataclasses.dataclass
class LinearRows:
    """Constraint rows affine in the design variables, ``G x + h ≥ 0`` [m], over named variables.

    The clearance and mounting constraints (:mod:`springbalance.design.clearance`) are such rows,
    linearised at the current design. They are kept by variable *name*, so that a problem with
    some other variables fixed (:meth:`DesignProblem.with_springs`) takes them over.

    Attributes:
        names: the design variables the rows depend on.
        matrix: ``G`` (rows × names) [m per unit of each variable].
        offset: ``h`` (rows) [m].
        labels: what each row keeps (e.g. ``"s1 clear of link2 at pose 17"``).
        scale: a typical size of a violation [m], for the solvers' scaling.
    """

    names: list
    matrix: np.ndarray
    offset: np.ndarray
    labels: list
    scale: float = 0.001

    def __len__(self) -> int:
        return int(self.offset.size)


def stacked_rows(first: LinearRows | None, second: LinearRows | None) -> LinearRows | None:
    """The rows of ``first`` then those of ``second``, over the union of their variable names (None when
    both are empty); the smaller of their scales."""
    if first is None or not len(first):
        return second
    if second is None or not len(second):
        return first
    names = list(dict.fromkeys(list(first.names) + list(second.names)))

    def widened(rows: LinearRows) -> np.ndarray:
        matrix = np.zeros((len(rows), len(names)))
        matrix[:, [names.index(name) for name in rows.names]] = rows.matrix
        return matrix

    return LinearRows(
        names,
        np.vstack([widened(first), widened(second)]),
        np.concatenate([first.offset, second.offset]),
        list(first.labels) + list(second.labels),
        min(first.scale, second.scale),
    )
