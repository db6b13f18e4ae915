r"""Meshcat scene of a design: the arm, its springs drawn as helices, and an animation.

What is drawn (all lengths in m, forces in N):

- the arm, through Pinocchio's ``MeshcatVisualizer`` with the URDF's visual geometry
  (meshes of example-robot-data included); a mechanism without visual geometry is drawn
  as a stick figure of its joints, links and centres of mass;
- every spring as a **helix** (a tube along a helical centre line with a straight hook at
  each end) from its end ``x_a`` to its end ``x_b``, coloured by its tension ``F(L)`` on a
  :class:`ColorScale` (warm colours for tension, greens for compression) that the static
  page shows as a legend; the legend's scale reaches into compression ("negative: pushing")
  only when some spring really pushes (tension below zero) in some frame of the animation;
- with a **clearance margin** ``m`` [m] (the ``margin`` argument, else the design problem's
  ``clearance.margin``) and a URDF with ``<collision>`` elements: in every frame where a
  spring's capsule (radius: half its coil's outer diameter, else the problem's
  ``clearance.radius``, else 0.01 m; see :func:`springbalance.model.collision.capsule_radius`)
  comes closer than ``m`` (or touches: distance ≤ 0) to the collision geometry of any body
  but its own two anchor bodies (the rule of :mod:`springbalance.results.clearance`), the
  spring is drawn in magenta (:data:`~springbalance.viz.colors.CLEARANCE_COLOR`) instead of
  its tension colour, and the legend gets a "below clearance margin (m mm)" entry; the signed
  distances [m] per frame are :attr:`SpringTrack.clearance`. Without collision geometry the
  springs keep their tension colours;
- the **name of each spring** as a text label (a sprite that always faces the camera) just
  above the middle of the spring, following it in the animation;
- a small sphere at each anchor, and the free region of each anchor of the original
  problem (box, segment or plane rectangle of :mod:`springbalance.springs.params`) as a
  translucent shape fixed to its body;
- an animation along an ordered path of poses (by default a sweep of each joint in turn,
  :func:`springbalance.model.sweeps.animation_path`), with meshcat's play/pause/time controls.

The camera frames a sphere that holds, in every frame of the animation, the arm's links (the
bounding sphere of each visual shape), every spring with its coils, and every anchor region.
meshcat's orbit controls always look at the world origin (the arm's base, usually) and turn the
view about it, so the camera looks at the origin from just far enough that all of it lies within
90 % of the half-angle of meshcat's 75° field of view (:func:`camera_distance`).

The helix is built once per spring in *axial* coordinates: ``x, y`` in metres, ``z`` the
fraction ``s ∈ [0, 1]`` of the spring's length, from ``(0, 0, 0)`` to ``(0, 0, 1)``. At a
pose the node of the spring gets the rigid placement ``(R, x_a)`` with ``R e_z = u`` and the
scale ``diag(1, 1, L)``, so a local point maps to

.. math:: x = x_a + R\,(x, y, L s)^T,

and the ends land exactly on ``x_a`` and ``x_a + L u = x_b``: the coils stretch and
squeeze with the spring while their radius stays put. The end points come from the
workspace kinematics (:mod:`springbalance.model.kinematics`), lengths and tensions from the
design's own evaluation (:meth:`DesignResult.evaluate_on`).

Nothing here is imported by the core modules; data flows result → scene.

Static export (:func:`scene_html`) records the scene in memory and asks meshcat's own
server code for its self-contained page (scripts and meshes inlined, no network), without
opening a socket. The live scene (:func:`show`) runs a meshcat server in a child process
that listens on 127.0.0.1 only (:mod:`springbalance.viz.server`).
"""

from __future__ import annotations

import dataclasses
import html
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin

with warnings.catch_warnings():
    # meshcat's server module imports zmq.eventloop.ioloop, deprecated since pyzmq 17
    warnings.simplefilter("ignore", DeprecationWarning)
    import meshcat
    import meshcat.animation
    import meshcat.commands
    import meshcat.geometry as mg

from springbalance.errors import InputError
from springbalance.model import sweeps
from springbalance.files import write_text_atomic
from springbalance.springs.params import Free, Plane, Segment
from springbalance.model.workspace import Workspace
from springbalance.viz.arm import stick_figure, visual_geometry
from springbalance.viz.colors import CLEARANCE_COLOR, CLEARANCE_RGB, ColorScale
from springbalance.viz.helix import HelixStyle, helix_centerline, helix_tube, placement, spring_rotation
from springbalance.viz.live import LiveScene, local_server
from springbalance.viz.recorder import SceneRecorder

#: Meshcat path (below ``/meshcat``) of everything springbalance draws besides the arm.
ROOT = "springbalance"
ANCHOR_COLOR = 0x333333
#: a routed spring's cable (docs/model.md §3.9): a thin dark line from the spring's end over its pulleys
CABLE_COLOR = 0x222222
CABLE_RADIUS = 0.0015  # [m]
REGION_COLOR = 0x8c6bb1
REGION_OPACITY = 0.12
#: Height of a spring's name label [px] on its 256 px canvas texture (smaller for long names).
LABEL_FONT_SIZE = 40
#: Side of a label's square sprite as a fraction of the camera's distance from what it frames.
LABEL_SIZE = 0.22
#: Field of view (vertical) of meshcat's default camera [deg].
CAMERA_FOV = 75.0
#: Fraction of the half field of view that the framed sphere may fill.
CAMERA_FILL = 0.9


# ====================================================================== scene data
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
            spring is drawn magenta there), or None when no clearance is checked.
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
    #: a routed spring's cable per pose (N×K×3) [m]: the spring's moving end, the pulleys, the cable's end
    cable: np.ndarray | None = None
    #: world position per pose (N×3) [m] of every point of the spring's path by end name (a, via1 …, b)
    anchor_points: dict | None = None

    def points_by_end(self) -> dict:
        """World positions (N×3) [m] of the spring's anchor points by end name."""
        return self.anchor_points if self.anchor_points is not None else {"a": self.starts, "b": self.ends}

    def cable_placement(self, segment: int, frame: int) -> tuple[np.ndarray, float]:
        """Cable segment ``segment`` at pose ``frame``: the rigid placement (4×4) of a unit cylinder
        (axis y) at the segment's middle along it, and the segment's length [m] (its y scale)."""
        start, end = self.cable[frame, segment], self.cable[frame, segment + 1]
        direction = end - start
        length = float(np.linalg.norm(direction))
        rotation = spring_rotation(direction if length > 0 else np.array([0.0, 0.0, 1.0]), self.side)
        # spring_rotation takes e_z to the direction; the cylinder's axis is y: turn y onto z first
        y_to_z = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
        return placement(rotation @ y_to_z, (start + end) / 2), max(length, 1e-9)

    def cable_transform(self, segment: int, frame: int) -> np.ndarray:
        """Full node transform (4×4) of cable segment ``segment`` at pose ``frame`` (scaled to its length)."""
        rigid, length = self.cable_placement(segment, frame)
        return rigid @ np.diag([1.0, length, 1.0, 1.0])

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

    def mesh(self):
        """Vertices (axial coordinates) and faces of the helix tube."""
        return helix_tube(self.centerline(), self.wire_radius, self.reference_length, self.sides)


@dataclasses.dataclass
class RegionShape:
    """The free region of one anchor, in its body's frame.

    ``kind`` is ``"box"`` (centre and size [m]), ``"segment"`` (from ``start`` to ``end``
    [m]) or ``"plane"`` (the four corners [m] of the rectangle). ``placements`` holds
    the body's world placement per pose (N×4×4).
    """

    spring: str
    end: str
    body: str
    kind: str
    corners: np.ndarray
    placements: np.ndarray


class DesignScene:
    """Everything needed to draw a design along an ordered path of poses.

    Args:
        result (DesignResult): the :class:`~springbalance.results.result.DesignResult`.
        joint_values (numpy.ndarray | None): the path (N×nv joint coordinates [rad or m]); default
            :func:`~springbalance.model.sweeps.animation_path` (a sweep of each joint).
        frames_per_joint: frames of each joint's sweep in the default path.
        style: :class:`HelixStyle`.
        fps: frames per second of the animation.
        margin: clearance margin [m] (≥ 0): a spring is drawn magenta in the frames where its
            capsule is closer than this to the arm's collision geometry (see the module
            documentation). Default: ``result.problem.clearance.margin`` when the problem has a
            clearance, else no clearance is drawn. Ignored (no error) when the URDF has no
            ``<collision>`` elements; :attr:`clearance_note` then says why.

    Attributes:
        springs: one :class:`SpringTrack` per drawn (two-point) spring.
        skipped: the springs left out of the drawing (torsional springs), by name.
        color_scale: the :class:`ColorScale` of the tensions [N].
        compression: True when some drawn spring pushes (negative tension) in some frame.
        margin: the clearance margin [m], or None.
        clearance_note: why no clearance is drawn although a margin is set (else None).
        camera_center, camera_radius: the sphere [m] the camera frames (:meth:`bounding_spheres`);
        camera_target, camera_position: where the camera looks (the world origin, meshcat's orbit
            target) and where it stands (world, [m]). The four are set by :meth:`draw`.
    """

    def __init__(self, result, joint_values=None, frames_per_joint: int = 48, style: HelixStyle = HelixStyle(),
                 fps: int = 30, margin: float | None = None):
        self.result = result
        mechanism = result.problem.mechanism
        self.mechanism = mechanism
        if joint_values is None:
            joint_values = sweeps.animation_path(result, frames_per_joint)
        self.workspace = Workspace.from_array(mechanism, joint_values, ordered=True)
        self.joint_values = self.workspace.joint_values
        self.configurations = self.workspace.configurations
        self.fps = int(fps)
        self.style = style
        self.evaluation = result.evaluate_on(self.workspace)   # lengths and tensions from the model
        kinematics = self.workspace.kinematics()
        self.springs: list[SpringTrack] = []
        self._records: dict[str, dict] = {}
        columns = []
        for column, (spring, record) in enumerate(zip(result.problem.springs, result.springs)):
            if getattr(spring, "ends", ()) != ("a", "b"):   # a joint spring (torsional) has no ends to draw a helix between
                continue
            columns.append(column)
            lengths = self.evaluation.lengths[:, column]
            path = {end: kinematics.body(record[end]["body"]).points(np.array(record[end]["point"]))
                    for end in spring.anchors}
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
            self.springs.append(SpringTrack(
                record["name"], record["type"], (a["body"], b["body"]), np.array([a["point"], b["point"]]),
                starts, ends, lengths.copy(), self.evaluation.tensions[:, column].copy(), side, int(style.coils),
                coil, wire, reference, style.lead, style.points_per_coil, style.sides, cable=cable,
                anchor_points=path if cable is not None else None))
            self._records[record["name"]] = record
        #: the springs left out of the drawing (torsional springs), by name
        self.skipped = [record["name"] for column, record in enumerate(result.springs) if column not in columns]
        path_tensions = self.evaluation.tensions[:, columns]
        design_tensions = result.evaluation.tensions[:, columns]
        self.color_scale = ColorScale.for_tensions(path_tensions, design_tensions)
        # the legend's compression half is for springs that push in the animation, not for laws that could
        self.compression = bool(np.any(self.color_scale.pushes(path_tensions)))
        self.regions = self._regions(kinematics)
        self.margin, self.clearance_note = self._margin(margin), None
        if self.margin is not None:
            self._clearances()
        self.camera_center: np.ndarray | None = None
        self.camera_radius: float | None = None
        self.camera_target: np.ndarray | None = None
        self.camera_position: np.ndarray | None = None

    def _margin(self, margin) -> float | None:
        """The margin [m] asked for, else the problem's clearance margin (``DesignProblem.clearance``), else None."""
        clearance = getattr(self.result.problem, "clearance", None)
        if margin is None and clearance is not None:
            margin = getattr(clearance, "margin", None)
        if margin is None:
            return None
        if (isinstance(margin, bool) or not isinstance(margin, (int, float, np.integer, np.floating))
                or not (np.isfinite(margin) and margin >= 0)):
            raise InputError(f"clearance margin must be a finite number ≥ 0 [m], got {margin!r}")
        return float(margin)

    def _clearances(self) -> None:
        """Per frame and spring, the smallest signed distance [m] from the spring's capsule to the
        collision objects of the bodies it is not anchored to (:mod:`springbalance.results.clearance`)."""
        from springbalance.model.collision import CollisionScene, capsule_radius

        try:
            collision = CollisionScene(self.mechanism)
        except InputError as error:   # no URDF, or no <collision> elements: the scene is drawn without
            self.clearance_note = str(error)
            return
        radius = getattr(getattr(self.result.problem, "clearance", None), "radius", None)
        checked = {}
        for track in self.springs:
            track.radius = capsule_radius(self._records[track.name], radius)
            track.clearance = np.full(self.size, np.inf)
            checked[track.name] = collision.indices_except(track.bodies)
        for frame, q in enumerate(self.configurations):
            collision.place(q)
            for track in self.springs:
                for index in checked[track.name]:
                    distance = collision.capsule_distance(track.starts[frame], track.ends[frame], track.radius,
                                                          index).distance
                    track.clearance[frame] = min(track.clearance[frame], distance)
        for track in self.springs:
            finite = np.isfinite(track.clearance)
            track.below_margin = finite & ((track.clearance < self.margin) | (track.clearance <= 0))

    @property
    def clearance_violated(self) -> bool:
        """True when some spring is below the clearance margin in some frame (it is drawn magenta)."""
        return any(track.below_margin is not None and bool(np.any(track.below_margin)) for track in self.springs)

    def rgb(self, spring: SpringTrack, frame: int) -> tuple[float, float, float]:
        """Colour (RGB in [0, 1]) of ``spring`` at pose ``frame``: magenta below the clearance margin,
        else the colour of its tension."""
        if spring.below_margin is not None and spring.below_margin[frame]:
            return CLEARANCE_RGB
        return self.color_scale.rgb(spring.tensions[frame])

    def hex(self, spring: SpringTrack, frame: int) -> int:
        """:meth:`rgb` as the 0xRRGGBB integer that meshcat materials take."""
        if spring.below_margin is not None and spring.below_margin[frame]:
            return CLEARANCE_COLOR
        return self.color_scale.hex(spring.tensions[frame])

    def legend_html(self, position: str = "fixed") -> str:
        """The colour legend of the scene (see :meth:`ColorScale.legend_html`): the tension scale, its
        compression half only when some spring pushes, the clearance entry only when some spring is
        below the margin."""
        return self.color_scale.legend_html(self.compression, position=position,
                                            clearance_margin=self.margin if self.clearance_violated else None)

    @property
    def size(self) -> int:
        """Number of poses (animation frames)."""
        return self.workspace.size

    def _regions(self, kinematics) -> list[RegionShape]:
        regions = []
        for spring in self.result.problem.springs:
            for end, anchor in _anchors(spring).items():
                if getattr(anchor, "mount", None) == "collision":
                    continue    # mounted on the link's own surface: the link is the mounting surface drawn
                corners = _region_corners(anchor.point)
                if corners is None:
                    continue
                kind, points = corners
                body = kinematics.body(anchor.body)
                placements = np.zeros((self.size, 4, 4))
                placements[:, :3, :3] = body.rotation
                placements[:, :3, 3] = body.translation
                placements[:, 3, 3] = 1.0
                regions.append(RegionShape(spring.name, end, anchor.body, kind, points, placements))
        return regions

    # ---------------------------------------------------------------- drawing
    def draw(self, visualizer, animate: bool = True, autoplay: bool = True) -> None:
        """Draw the scene on a ``meshcat.Visualizer`` (live or recording)."""
        arm = self._arm_visualizer(visualizer)
        arm.display(self.configurations[0])
        visualizer["/Background"].set_property("top_color", [1.0, 1.0, 1.0])
        visualizer["/Background"].set_property("bottom_color", [0.8, 0.83, 0.88])
        visualizer["/Axes"].set_property("visible", False)
        self._set_camera(visualizer, arm)

        root = visualizer[ROOT]
        helix_objects = {}
        label_size = LABEL_SIZE * float(np.linalg.norm(self.camera_position - self.camera_target))  # [m], a side
        for spring in self.springs:
            vertices, faces = spring.mesh()
            node = root["springs"][spring.name]
            mesh = mg.Mesh(mg.TriangularMeshGeometry(vertices, faces),
                           mg.MeshPhongMaterial(color=self.hex(spring, 0), shininess=40))
            helix_objects[spring.name] = mesh.uuid
            node.set_object(mesh)
            node.set_transform(spring.transform(0))
            label = root["labels"][spring.name]
            label.set_object(_TextSprite(spring.name, label_size))
            label.set_transform(placement(np.eye(3), self.label_positions(spring)[0]))
            for end, positions in spring.points_by_end().items():
                sphere = root["anchors"][f"{spring.name}.{end}"]
                sphere.set_object(mg.Sphere(1.6 * spring.wire_radius + 0.004), mg.MeshPhongMaterial(color=ANCHOR_COLOR))
                sphere.set_transform(placement(np.eye(3), positions[0]))
            if spring.cable is not None:
                for segment in range(spring.cable.shape[1] - 1):
                    node = root["cables"][spring.name][f"segment{segment}"]
                    node.set_object(mg.Cylinder(1.0, CABLE_RADIUS), mg.MeshPhongMaterial(color=CABLE_COLOR))
                    node.set_transform(spring.cable_transform(segment, 0))
        for region in self.regions:
            node = root["regions"][f"{region.spring}.{region.end}"]
            geometry, edges = _region_geometry(region)
            node["shape"].set_object(geometry, mg.MeshLambertMaterial(color=REGION_COLOR, opacity=REGION_OPACITY,
                                                                      transparent=True, depthWrite=False))
            node["edges"].set_object(mg.LineSegments(mg.PointsGeometry(edges.T),
                                                     mg.LineBasicMaterial(color=REGION_COLOR, opacity=0.7,
                                                                          transparent=True)))
            node.set_transform(region.placements[0])
        if animate and self.size > 1:
            visualizer.window.send(_SetAnimation(self.animation(visualizer, arm, helix_objects), play=autoplay,
                                                 repetitions=float("inf")))

    def animation(self, visualizer, arm, helix_objects: dict[str, str]):
        """The meshcat animation of the path: arm, springs (stretch and colour), name labels, anchors, regions.

        ``helix_objects`` maps each spring to the uuid of its helix mesh, which the colour
        track addresses (three.js finds a node's child object by name or uuid).
        """
        animation = _Animation(default_framerate=self.fps)
        model, data = arm.model, arm.model.createData()
        visual_model, visual_data = arm.visual_model, arm.visual_model.createData()
        names = [arm.getViewerNodeName(geometry, pin.GeometryType.VISUAL) for geometry in visual_model.geometryObjects]
        labels = {spring.name: self.label_positions(spring) for spring in self.springs}
        for frame, q in enumerate(self.configurations):
            with animation.at_frame(visualizer, frame) as at:
                pin.forwardKinematics(model, data, q)
                pin.updateGeometryPlacements(model, data, visual_model, visual_data)
                for index, (name, geometry) in enumerate(zip(names, visual_model.geometryObjects)):
                    at[name].set_transform(visual_data.oMg[index].homogeneous)
                    if not np.allclose(geometry.meshScale, 1.0):
                        at[name].set_property("scale", "vector3", [float(s) for s in geometry.meshScale])
                root = at[ROOT]
                for spring in self.springs:
                    node = root["springs"][spring.name]
                    node.set_transform(spring.rigid_transform(frame))
                    node.set_property("scale", "vector3", [1.0, 1.0, spring.length(frame)])
                    node.set_property(f"{helix_objects[spring.name]}.material.color", "color",
                                      list(self.rgb(spring, frame)))
                    root["labels"][spring.name].set_transform(placement(np.eye(3), labels[spring.name][frame]))
                    for end, positions in spring.points_by_end().items():
                        root["anchors"][f"{spring.name}.{end}"].set_transform(placement(np.eye(3), positions[frame]))
                    if spring.cable is not None:
                        for segment in range(spring.cable.shape[1] - 1):
                            rigid, length = spring.cable_placement(segment, frame)
                            node = root["cables"][spring.name][f"segment{segment}"]
                            node.set_transform(rigid)
                            node.set_property("scale", "vector3", [1.0, length, 1.0])
                for region in self.regions:
                    root["regions"][f"{region.spring}.{region.end}"].set_transform(region.placements[frame])
        return animation

    def _visual_model(self):
        """The arm's visual geometry: the URDF's, or a stick figure when it has none."""
        visual_model = visual_geometry(self.mechanism)
        if visual_model is None or visual_model.ngeoms == 0:
            visual_model = stick_figure(self.mechanism.model)
        return visual_model

    def _arm_visualizer(self, visualizer):
        from pinocchio.visualize import MeshcatVisualizer

        arm = MeshcatVisualizer(self.mechanism.model, None, self._visual_model())
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # pinocchio warns about geometry it cannot show; the rest is drawn
            arm.initViewer(viewer=visualizer)
            arm.loadViewerModel(rootNodeName="pinocchio")
        return arm

    def label_positions(self, spring: SpringTrack) -> np.ndarray:
        """Where the name label of ``spring`` sits per pose (N×3) [m]: just above its middle (world +z,
        by its coil radius plus its wire), so the text stands over the helix."""
        return spring.midpoints() + np.array([0.0, 0.0, spring.coil_radius + spring.wire_radius + 0.004])

    def bounding_spheres(self, visual_model=None) -> tuple[np.ndarray, np.ndarray]:
        """Centres (K×3) [m] and radii (K) [m] of spheres that hold, over every frame, what is drawn:

        - each spring's two ends, with its coil radius plus its wire radius (so the coils are held);
        - the corners of each anchor region on its body;
        - each joint's and frame's origin, and the bounding sphere of each shape of ``visual_model``
          (the arm's links; default: the URDF's visual geometry, or the stick figure).
        """
        centres, radii = [], []
        for spring in self.springs:
            reach = spring.coil_radius + spring.wire_radius
            for points in (spring.starts, spring.ends, *spring.points_by_end().values()):
                centres.append(points)
                radii.append(np.full(len(points), reach))
        for region in self.regions:
            corners = _region_points(region)
            world = np.einsum("nij,kj->nki", region.placements[:, :3, :3], corners) + region.placements[:, None, :3, 3]
            centres.append(world.reshape(-1, 3))
            radii.append(np.zeros(world.shape[0] * world.shape[1]))
        model = self.mechanism.model
        if visual_model is None:
            visual_model = self._visual_model()
        data, visual_data = model.createData(), visual_model.createData()
        shapes = []   # (local centre, radius) of each visual shape's bounding sphere
        for geometry in visual_model.geometryObjects:
            try:
                geometry.geometry.computeLocalAABB()
                shapes.append((np.array(geometry.geometry.aabb_center), float(geometry.geometry.aabb_radius)))
            except (AttributeError, RuntimeError):
                shapes.append((np.zeros(3), 0.0))
        for q in self.configurations:
            pin.forwardKinematics(model, data, q)
            pin.updateFramePlacements(model, data)
            pin.updateGeometryPlacements(model, data, visual_model, visual_data)
            centres.append(np.array([data.oMi[j].translation for j in range(model.njoints)]))
            centres.append(np.array([data.oMf[f].translation for f in range(model.nframes)]))
            radii += [np.zeros(model.njoints), np.zeros(model.nframes)]
            if shapes:
                centres.append(np.array([visual_data.oMg[i].act(centre) for i, (centre, _) in enumerate(shapes)]))
                radii.append(np.array([radius for _, radius in shapes]))
        return np.vstack(centres), np.concatenate(radii)

    def _set_camera(self, visualizer, arm) -> None:
        """Frame everything drawn over the whole animation (:meth:`bounding_spheres`): look at the world
        origin (meshcat's orbit target) from the side that shows the motion best, far enough that
        every bounding sphere is in view (:func:`camera_distance`)."""
        centres, radii = self.bounding_spheres(arm.visual_model)
        lower, upper = (centres - radii[:, None]).min(axis=0), (centres + radii[:, None]).max(axis=0)
        center = (lower + upper) / 2
        radius = max(float(np.max(np.linalg.norm(centres - center, axis=1) + radii)), 0.15)   # [m]
        # a planar arm is seen square-on (along the normal of its plane), any other from an oblique corner
        _, spread, axes = np.linalg.svd(centres - centres.mean(axis=0), full_matrices=False)
        if spread[-1] < 0.2 * spread[-2]:
            normal = axes[-1] if axes[-1] @ np.array([0.3, -1.0, 0.0]) >= 0 else -axes[-1]
            direction = normal + np.array([0.35, -0.25, 0.45])
        else:
            direction = np.array([1.0, -1.3, 0.8])
        direction /= np.linalg.norm(direction)
        position = camera_distance(centres, radii, direction) * direction    # [m] world
        self.camera_center, self.camera_radius = center, radius
        self.camera_target, self.camera_position = np.zeros(3), position
        # meshcat's orbit controls look at the world origin: the camera's parent frame must not move
        visualizer["/Cameras/default"].set_transform(np.eye(4))
        # the camera node is rotated by +90° about x (meshcat's y-up convention): world (x, y, z) = rotated (x, z, -y)
        visualizer["/Cameras/default/rotated/<object>"].set_property("position",
                                                                     [position[0], position[2], -position[1]])

    # ---------------------------------------------------------------- exports
    def html(self, animate: bool = True, autoplay: bool = True, legend: bool = True) -> str:
        """Self-contained HTML page of the scene (meshcat's static page plus the colour legend)."""
        recorder = SceneRecorder()
        visualizer = meshcat.Visualizer(window=recorder)
        self.draw(visualizer, animate=animate, autoplay=autoplay)
        page = visualizer.static_html()
        if legend:
            page = _insert_before_body_end(page, self.legend_html())
        return page


def camera_distance(centres, radii, direction, fov: float = CAMERA_FOV, fill: float = CAMERA_FILL) -> float:
    """Distance [m] from the world origin along the unit vector ``direction`` of a camera that looks at
    the origin and sees every sphere (``centres`` K×3 [m], ``radii`` K [m]) within ``fill`` of the half
    field of view ``fov`` [deg]: for each sphere, the angle between the line of sight and its centre
    plus its angular radius is at most ``fill · fov / 2``. The smallest such distance, by bisection
    (beyond every sphere both angles only shrink with the distance)."""
    centres = np.atleast_2d(np.asarray(centres, dtype=float))
    radii = np.asarray(radii, dtype=float)
    direction = np.asarray(direction, dtype=float)
    half = np.radians(fill * fov / 2)

    def angle(distance: float) -> float:
        to_centres = centres - distance * direction
        reach = np.linalg.norm(to_centres, axis=1)
        sight = np.arccos(np.clip(-(to_centres @ direction) / reach, -1.0, 1.0))
        return float(np.max(sight + np.arcsin(np.minimum(radii / reach, 1.0))))

    low = float(np.max(np.linalg.norm(centres, axis=1) + radii))     # outside every sphere
    high = 2 * low / np.sin(half) + 1e-3
    for _ in range(60):
        middle = (low + high) / 2
        low, high = (middle, high) if angle(middle) > half else (low, middle)
    return high


def _anchors(spring) -> dict:
    """The spring's anchors by end name (none for a spring that acts in a joint)."""
    anchors = getattr(spring, "anchors", None)
    if isinstance(anchors, dict):
        return anchors
    return {end: getattr(spring, end) for end in ("a", "b") if hasattr(spring, end)}


def _region_corners(point):
    """``(kind, points)`` describing an anchor's free region in the body frame, or None if fixed."""
    if isinstance(point, Segment):
        lower, upper = float(point.bounds.lower), float(point.bounds.upper)
        direction = point.end - point.start
        return "segment", np.array([point.start + lower * direction, point.start + upper * direction])
    if isinstance(point, Plane):
        (s0, t0), (s1, t1) = point.bounds.lower, point.bounds.upper
        corners = [point.origin + s * point.u + t * point.v for s, t in ((s0, t0), (s1, t0), (s1, t1), (s0, t1))]
        return "plane", np.array(corners)
    if isinstance(point, Free):
        if not np.any(point.upper > point.lower):
            return None
        return "box", np.array([point.lower, point.upper])
    return None


def _region_geometry(region: RegionShape):
    """Meshcat geometry of the region in body coordinates (a box, or a thin rod or sheet where
    flat) and the end points of its edges (2E×3, pairs for ``LineSegments``)."""
    thickness = 0.004  # [m] of a box side with no width, and of rods and sheets
    if region.kind == "box":
        lower, upper = region.corners
        size = np.maximum(upper - lower, thickness)
        vertices, faces = _box_mesh((lower + upper) / 2, size, np.eye(3))
        edges = vertices[_BOX_EDGES.ravel()]
    elif region.kind == "segment":
        start, end = region.corners
        axis = end - start
        length = float(np.linalg.norm(axis))
        rotation = spring_rotation(axis, np.eye(3)[int(np.argmin(np.abs(axis)))]) if length > 0 else np.eye(3)
        vertices, faces = _box_mesh((start + end) / 2, np.array([thickness, thickness, max(length, thickness)]), rotation)
        edges = np.array([start, end])
    else:
        c = region.corners
        normal = np.cross(c[1] - c[0], c[3] - c[0])
        normal = thickness / 2 * normal / np.linalg.norm(normal)
        vertices = np.vstack([c - normal, c + normal])
        faces = np.array([[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6], [0, 4, 5], [0, 5, 1], [1, 5, 6], [1, 6, 2],
                          [2, 6, 7], [2, 7, 3], [3, 7, 4], [3, 4, 0]])
        edges = c[[0, 1, 1, 2, 2, 3, 3, 0]]
    return mg.TriangularMeshGeometry(vertices, faces), np.asarray(edges, dtype=np.float32)


def _region_points(region: RegionShape) -> np.ndarray:
    """Points (body frame) [m] whose convex hull is the region: a box's 8 corners, a segment's ends,
    a rectangle's 4 corners."""
    if region.kind == "box":
        lower, upper = region.corners
        return np.array([[(lower, upper)[i][0], (lower, upper)[j][1], (lower, upper)[k][2]]
                         for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    return np.asarray(region.corners, dtype=float)


#: vertex pairs of the 12 edges of :func:`_box_mesh` (vertex index bits: x, y, z)
_BOX_EDGES = np.array([[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]])


def _box_mesh(center, size, rotation):
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    vertices = center + (signs * size / 2) @ np.asarray(rotation).T
    faces = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return vertices, faces


def _insert_before_body_end(page: str, fragment: str) -> str:
    index = page.rfind("</body>")
    return page[:index] + fragment + page[index:] if index >= 0 else page + fragment


class _TextTexture(mg.Texture):
    """meshcat's ``_text`` texture: the viewer draws ``text`` centred on a 256×256 px canvas
    (``font_size`` px, smaller when the text is wider than the canvas)."""

    def __init__(self, text: str, font_size: int = LABEL_FONT_SIZE, font_face: str = "sans-serif"):
        super().__init__()
        self.text, self.font_size, self.font_face = str(text), int(font_size), font_face

    def lower(self, object_data):
        return {"uuid": self.uuid, "type": "_text", "text": self.text, "font_size": self.font_size,
                "font_face": self.font_face}


class _SpriteMaterial(mg.Material):
    """three.js ``SpriteMaterial`` showing a texture, drawn over everything (no depth test)."""

    def __init__(self, texture: mg.Texture):
        super().__init__()
        self.texture = texture

    def lower(self, object_data):
        return {"uuid": self.uuid, "type": "SpriteMaterial", "color": 0xFFFFFF, "transparent": True,
                "depthTest": False, "depthWrite": False, "sizeAttenuation": True,
                "map": self.texture.lower_in_object(object_data)}


class _TextSprite(mg.Object):
    """A text label: a three.js ``Sprite`` (a square that always faces the camera) of side ``size``
    [m], centred on its node, with ``text`` on it (meshcat's ``_text`` texture)."""

    def __init__(self, text: str, size: float):
        super().__init__(None, _SpriteMaterial(_TextTexture(text)))
        self.text, self.size = text, float(size)

    def lower(self):
        data = {"metadata": {"version": 4.5, "type": "Object"}, "geometries": [], "materials": [], "textures": [],
                "images": [],
                "object": {"uuid": self.uuid, "type": "Sprite", "name": self.text, "material": self.material.uuid,
                           "matrix": list(np.diag([self.size, self.size, 1.0, 1.0]).flatten())}}
        self.material.lower_in_object(data)
        return data


class _Animation(meshcat.animation.Animation):
    """meshcat's Animation, plus tracks of a property of a node's object (``<uuid>.material.color``).

    meshcat names every track ``.<property>``, a property of the node (a group); a track of
    the object inside the group must be named ``<uuid of the object>.material.color``.
    """

    __slots__ = ()

    def lower(self):
        lowered = super().lower()
        for item in lowered:
            for track in item["clip"]["tracks"]:
                if ".material." in track["name"]:
                    track["name"] = track["name"].lstrip(".")
        return lowered


class _SetAnimation(meshcat.commands.SetAnimation):
    """meshcat's set_animation command, kept in the server's scene tree *after* the objects.

    A meshcat server (and :class:`SceneRecorder`) stores a command at the tree node of its
    path and replays the tree depth first to every new browser and into the static page.
    meshcat's own command has the empty path, the root, so it replays *before* the objects,
    and tracks of an object that does not exist yet (the helix colour) fail to bind. This
    one is stored at a top-level node created after the scene. The browser ignores the path.
    """

    __slots__ = ()

    def lower(self):
        data = super().lower()
        data["path"] = f"/{ROOT}-animation"
        return data


class StaticScene:
    """A self-contained scene page; in Jupyter it shows inline without any server."""

    def __init__(self, page: str):
        self.page = page

    def save(self, path: str | Path) -> Path:
        return write_text_atomic(path, self.page)

    def _repr_html_(self) -> str:
        return (f'<iframe srcdoc="{html.escape(self.page, quote=True)}" style="width:100%;height:480px;border:none">'
                '</iframe>')

    def __repr__(self) -> str:
        return f"StaticScene({len(self.page)} characters)"


def scene_html(result, joint_values=None, animate: bool = True, autoplay: bool = True, legend: bool = True,
               **options) -> str:
    """The self-contained HTML page of a design's scene (no server, no network); ``options`` go to
    :class:`DesignScene` (``frames_per_joint``, ``style``, ``fps``, ``margin`` [m])."""
    return DesignScene(result, joint_values, **options).html(animate=animate, autoplay=autoplay, legend=legend)


def save_scene_html(result, path: str | Path, **options) -> Path:
    """Write :func:`scene_html` to ``path`` (folders are created)."""
    return write_text_atomic(path, scene_html(result, **options))


def show(result, joint_values=None, static: bool = False, open_browser: bool = False, port: int | None = None,
         **options):
    """Show a design in meshcat.

    ``static=True`` returns a :class:`StaticScene` (inline in Jupyter, no server). Otherwise
    the scene is drawn on the session's local server (:func:`local_server`, 127.0.0.1 only)
    and a :class:`LiveScene` with its URL is returned. ``options`` go to :class:`DesignScene`
    (``frames_per_joint``, ``style``, ``fps``, ``margin`` [m]).
    """
    scene = DesignScene(result, joint_values, **options)
    if static:
        return StaticScene(scene.html())
    server = local_server(port)
    visualizer = server.visualizer()
    visualizer.delete()
    scene.draw(visualizer)
    if open_browser:
        import webbrowser

        webbrowser.open(server.web_url, new=2)
    return LiveScene(scene, server, visualizer)
