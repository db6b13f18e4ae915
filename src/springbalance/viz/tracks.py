"""A spring along the path of poses (:class:`SpringTrack`): where its ends are, how long and how taut
it is, how its helix is drawn, and how close it comes to the arm (the clearance check).

The helix is built once per spring in *axial* coordinates: ``x, y`` in metres, ``z`` the
fraction ``s ∈ [0, 1]`` of the spring's length, from ``(0, 0, 0)`` to ``(0, 0, 1)``. At a
pose the node of the spring gets the rigid placement ``(R, x_a)`` with ``R e_z = u`` and the
scale ``diag(1, 1, L)``, so a local point maps to ``x = x_a + R (x, y, L s)^T``; the ends land
exactly on ``x_a`` and ``x_a + L u = x_b``: the coils stretch and squeeze with the spring while
their radius stays put.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.errors import InputError
from springbalance.model.collision import CollisionScene, capsule_radius
from springbalance.model.kinematics import WorkspaceKinematics
from springbalance.model.mechanism import Mechanism
from springbalance.springs.laws.spring import Spring
from springbalance.viz.helix import HelixStyle, helix_centerline, helix_tube, placement, spring_rotation


@dataclasses.dataclass
class SpringTrack:
    """One spring along the path of poses.

    Attributes:
        name, kind: the spring's name and law.
        bodies: bodies of ends a and b; points: their body-frame points [m] (2×3).
        starts, ends: world positions of ends a and b per pose (N×3) [m].
        lengths: length per pose (N) [m]; tensions: tension per pose (N) [N].
        side: reference vector that fixes the helix's roll.
        coils, coil_radius [m], wire_radius [m], reference_length [m]: the drawing.
        radius: capsule radius [m] of the clearance check (None when there is none).
        clearance: per pose, the smallest signed distance [m] from the spring's capsule to the
            collision objects of every body but its two anchor bodies (negative: overlap;
            ``inf`` when there is nothing to check), or None when no clearance is checked.
        below_margin: per pose, True where ``clearance`` is below the margin or ≤ 0 (the
            spring is drawn red there), or None when no clearance is checked.
        closest: per pose, the world point [m] halfway between the spring's capsule and the nearest
            collision object (N×3; NaN where nothing is checked), or None.
        inside: per pose, how deep [m] the spring's centre line runs inside its own anchor bodies beyond its
            anchors (0 where it does not), or None when that is not checked (:mod:`springbalance.viz.own_link_marks`).
        inside_point: per pose, the world point [m] halfway between the deepest point of that centre line and
            the body's surface nearest it (N×3; NaN where it does not run inside), or None.
    """

    name: str
    kind: str
    bodies: tuple[str, str]
    points: np.ndarray
    starts: np.ndarray
    ends: np.ndarray
    lengths: np.ndarray
    tensions: np.ndarray
    side: np.ndarray
    coils: int
    coil_radius: float
    wire_radius: float
    reference_length: float
    lead: float
    points_per_coil: int
    sides: int
    radius: float | None = None
    clearance: np.ndarray | None = None
    below_margin: np.ndarray | None = None
    closest: np.ndarray | None = None
    inside: np.ndarray | None = None
    inside_point: np.ndarray | None = None
    #: a routed spring's cable per pose (N×K×3) [m]: the spring's moving end, the pulleys, the cable's end
    cable: np.ndarray | None = None
    #: world position per pose (N×3) [m] of every point of the spring's path by end name (a, via1 …, b)
    anchor_points: dict | None = None
    #: the foot of the bracket that holds an anchor off its link, world position per pose (N×3) [m] by end
    #: name (:func:`~springbalance.viz.rods.add_brackets`), or None when no anchor stands off its link
    brackets: dict | None = None
    #: per end name with a bracket, whether its straight line passes through another link at each pose (N)
    brackets_through: dict | None = None
    #: the uuid of each bracket's mesh by its node name (set when the scene is drawn; its colour is animated)
    rod_meshes: dict | None = None

    def points_by_end(self) -> dict:
        """World positions (N×3) [m] of the spring's anchor points by end name."""
        return self.anchor_points if self.anchor_points is not None else {"a": self.starts, "b": self.ends}

    def midpoints(self) -> np.ndarray:
        """The middle of the spring per pose (N×3) [m]."""
        return (self.starts + self.ends) / 2

    def rigid_transform(self, frame: int) -> np.ndarray:
        """Placement (4×4) of the spring's node at pose ``frame``: origin ``x_a``, ``R e_z = u``."""
        return placement(spring_rotation(self.ends[frame] - self.starts[frame], self.side), self.starts[frame])

    def length(self, frame: int) -> float:
        """Distance of the ends [m] at pose ``frame`` (the scale of the axial coordinate)."""
        return float(np.linalg.norm(self.ends[frame] - self.starts[frame]))

    def transform(self, frame: int) -> np.ndarray:
        """Full node transform at pose ``frame``: placement times ``diag(1, 1, L)``."""
        return self.rigid_transform(frame) @ np.diag([1.0, 1.0, self.length(frame), 1.0])

    def centerline(self) -> np.ndarray:
        """The helix centre line in axial coordinates (see :func:`helix_centerline`)."""
        return helix_centerline(self.coils, self.coil_radius, self.lead, self.points_per_coil)

    def helix_world(self, frame: int) -> np.ndarray:
        """The helix centre line in world coordinates at pose ``frame`` (M×3) [m]."""
        local = np.column_stack([self.centerline(), np.ones(len(self.centerline()))])
        return (self.transform(frame) @ local.T).T[:, :3]

    def mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """Vertices (axial coordinates) and faces of the helix tube."""
        return helix_tube(self.centerline(), self.wire_radius, self.reference_length, self.sides)


def rod_placement(start: np.ndarray, end: np.ndarray, side: np.ndarray) -> tuple[np.ndarray, float]:
    """A rod from ``start`` to ``end`` (world [m]): the rigid placement (4×4) of a unit cylinder (axis y) at its
    middle along it, and its length [m] (the cylinder's y scale); ``side`` fixes its roll."""
    direction = np.asarray(end, dtype=float) - np.asarray(start, dtype=float)
    length = float(np.linalg.norm(direction))
    rotation = spring_rotation(direction if length > 0 else np.array([0.0, 0.0, 1.0]), side)
    # spring_rotation takes e_z to the direction; the cylinder's axis is y: turn y onto z first
    y_to_z = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    return placement(rotation @ y_to_z, (np.asarray(start) + np.asarray(end)) / 2), max(length, 1e-9)


def spring_tracks(
    design: EvaluatedDesign,
    lengths: np.ndarray,
    tensions: np.ndarray,
    kinematics: WorkspaceKinematics,
    style: HelixStyle,
) -> tuple[list[SpringTrack], dict[str, dict], list[int]]:
    """The track of each two-point spring of ``design`` along a path of poses.

    ``lengths`` [m] and ``tensions`` [N] (N×S) are the design's evaluation on the path, one column
    per spring of the problem; ``kinematics`` that of the path's workspace. Returns the tracks, the
    springs' records by name, and the columns of the springs drawn (a spring that acts in a joint,
    torsional, has no ends to draw a helix between and is left out).
    """
    tracks: list[SpringTrack] = []
    records: dict[str, dict] = {}
    columns: list[int] = []
    for column, (spring, record) in enumerate(zip(design.problem.springs, design.springs)):
        if getattr(spring, "ends", ()) != ("a", "b"):  # a joint spring (torsional) has no ends to draw a helix between
            continue
        columns.append(column)
        tracks.append(_track(spring, record, lengths[:, column], tensions[:, column], kinematics, style))
        records[record["name"]] = record
    return tracks, records, columns


def _track(
    spring: Spring,
    record: dict,
    lengths: np.ndarray,
    tensions: np.ndarray,
    kinematics: WorkspaceKinematics,
    style: HelixStyle,
) -> SpringTrack:
    """The track of one two-point spring: its ends per pose from the kinematics, its helix from ``style``.

    A routed spring lies from its end a towards its first pulley, as long as its law says; its cable
    goes on from there over the pulleys to its last end.
    """
    path = {end: kinematics.body(record[end]["body"]).points(np.array(record[end]["point"])) for end in spring.anchors}
    cable = None
    if getattr(spring, "routed", False):
        # the spring lies from a towards the first pulley, as long as the law says; the cable goes on
        first, second = path["a"], path[list(spring.anchors)[1]]
        direction = (second - first) / np.linalg.norm(second - first, axis=1, keepdims=True)
        starts, ends = first, first + lengths[:, None] * direction
        cable = np.stack([ends, *list(path.values())[1:]], axis=1)
        a, b = record["a"], record[list(spring.anchors)[1]]
    else:
        a, b = record["a"], record["b"]
        starts, ends = path["a"], path["b"]
    reference = float(np.linalg.norm(ends[0] - starts[0])) or float(np.max(lengths)) or 0.1
    coil, wire = style.dimensions(reference)
    mean_direction = np.mean(ends - starts, axis=0)
    side = np.eye(3)[int(np.argmin(np.abs(mean_direction)))] if np.any(mean_direction) else np.eye(3)[0]
    return SpringTrack(
        record["name"],
        record["type"],
        (a["body"], b["body"]),
        np.array([a["point"], b["point"]]),
        starts,
        ends,
        lengths.copy(),
        tensions.copy(),
        side,
        int(style.coils),
        coil,
        wire,
        reference,
        style.lead,
        style.points_per_coil,
        style.sides,
        cable=cable,
        anchor_points=path if cable is not None else None,
    )


def add_clearances(
    tracks: list[SpringTrack],
    records: dict[str, dict],
    mechanism: Mechanism,
    configurations: np.ndarray,
    margin: float,
    radius: float | None = None,
) -> str | None:
    """Set :attr:`SpringTrack.clearance` and :attr:`SpringTrack.below_margin` of every track.

    Per pose (``configurations``, N×nq) and spring, the smallest signed distance [m] from the spring's
    capsule (radius :func:`~springbalance.model.collision.capsule_radius` of its record and ``radius``
    [m]) to the collision objects of the bodies it is not anchored to (the rule of
    :mod:`springbalance.results.clearance`); below ``margin`` [m], or ≤ 0, the spring is below the margin.
    Returns None, or why nothing was checked (no URDF, or no ``<collision>`` elements: the tracks are
    left as they are).
    """
    try:
        collision = CollisionScene(mechanism)
    except InputError as error:  # no URDF, or no <collision> elements: the scene is drawn without
        return str(error)
    checked = {}
    radii: list[float] = []
    clearances: list[np.ndarray] = []
    for track in tracks:
        track.radius = capsule_radius(records[track.name], radius)
        track.clearance = np.full(len(configurations), np.inf)
        track.closest = np.full((len(configurations), 3), np.nan)
        radii.append(track.radius)
        clearances.append(track.clearance)
        checked[track.name] = collision.indices_except(track.bodies)
    for frame, q in enumerate(configurations):
        collision.place(q)
        for track, capsule, clearance in zip(tracks, radii, clearances):
            for index in checked[track.name]:
                contact = collision.capsule_distance(track.starts[frame], track.ends[frame], capsule, index)
                if contact.distance < clearance[frame]:
                    clearance[frame] = contact.distance
                    track.closest[frame] = (contact.on_capsule + contact.on_object) / 2  # type: ignore[index]
    for track, clearance in zip(tracks, clearances):
        finite = np.isfinite(clearance)
        track.below_margin = finite & ((clearance < margin) | (clearance <= 0))
    return None
