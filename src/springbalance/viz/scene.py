r"""Meshcat scene of a design: the arm, its springs drawn as helices, and an animation.

What is drawn (all lengths in m, forces in N):

- the arm, through Pinocchio's ``MeshcatVisualizer`` with the URDF's visual geometry
  (meshes of example-robot-data included); a mechanism without visual geometry is drawn
  as a stick figure of its joints, links and centres of mass;
- every spring as a **helix** (a tube along a helical centre line with a straight hook at
  each end) from its end ``x_a`` to its end ``x_b``, coloured by its tension ``F(L)`` on a
  :class:`ColorScale` (warm colours for tension, greens for compression) that the static
  page shows as a legend;
- a small sphere at each anchor, and the free region of each anchor of the original
  problem (box, segment or plane rectangle of :mod:`springbalance.springs.params`) as a
  translucent shape fixed to its body;
- an animation along an ordered path of poses (by default a sweep of each joint in turn,
  :func:`springbalance.model.sweeps.animation_path`), with meshcat's play/pause/time controls.

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

from springbalance.model import sweeps
from springbalance.files import write_text_atomic
from springbalance.springs.params import Free, Plane, Segment
from springbalance.model.workspace import Workspace
from springbalance.viz.arm import stick_figure, visual_geometry
from springbalance.viz.colors import ColorScale
from springbalance.viz.helix import HelixStyle, helix_centerline, helix_tube, placement, spring_rotation
from springbalance.viz.live import LiveScene, local_server
from springbalance.viz.recorder import SceneRecorder

#: Meshcat path (below ``/meshcat``) of everything springbalance draws besides the arm.
ROOT = "springbalance"
ANCHOR_COLOR = 0x333333
REGION_COLOR = 0x8c6bb1
REGION_OPACITY = 0.12


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
    """

    def __init__(self, result, joint_values=None, frames_per_joint: int = 48, style: HelixStyle = HelixStyle(),
                 fps: int = 30):
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
        columns = []
        for column, (spring, record) in enumerate(zip(result.problem.springs, result.springs)):
            if tuple(spring.anchors) != ("a", "b"):   # a joint spring (torsional) has no ends to draw a helix between
                continue
            columns.append(column)
            a, b = record["a"], record["b"]
            starts = kinematics.body(a["body"]).points(np.array(a["point"]))
            ends = kinematics.body(b["body"]).points(np.array(b["point"]))
            lengths = self.evaluation.lengths[:, column]
            reference = float(np.linalg.norm(ends[0] - starts[0])) or float(np.max(lengths)) or 0.1
            coil, wire = style.dimensions(reference)
            mean_direction = np.mean(ends - starts, axis=0)
            side = np.eye(3)[int(np.argmin(np.abs(mean_direction)))] if np.any(mean_direction) else np.eye(3)[0]
            self.springs.append(SpringTrack(
                record["name"], record["type"], (a["body"], b["body"]), np.array([a["point"], b["point"]]),
                starts, ends, lengths.copy(), self.evaluation.tensions[:, column].copy(), side, int(style.coils),
                coil, wire, reference, style.lead, style.points_per_coil, style.sides))
        #: the springs left out of the drawing (torsional springs), by name
        self.skipped = [record["name"] for column, record in enumerate(result.springs) if column not in columns]
        path_tensions = self.evaluation.tensions[:, columns]
        design_tensions = result.evaluation.tensions[:, columns]
        self.color_scale = ColorScale.for_tensions(path_tensions, design_tensions)
        self.compression = bool(np.any(self.color_scale.pushes(path_tensions))
                                or np.any(self.color_scale.pushes(design_tensions)))
        self.regions = self._regions(kinematics)

    @property
    def size(self) -> int:
        """Number of poses (animation frames)."""
        return self.workspace.size

    def _regions(self, kinematics) -> list[RegionShape]:
        regions = []
        for spring in self.result.problem.springs:
            for end, anchor in _anchors(spring).items():
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
        for spring in self.springs:
            vertices, faces = spring.mesh()
            node = root["springs"][spring.name]
            mesh = mg.Mesh(mg.TriangularMeshGeometry(vertices, faces),
                           mg.MeshPhongMaterial(color=self.color_scale.hex(spring.tensions[0]), shininess=40))
            helix_objects[spring.name] = mesh.uuid
            node.set_object(mesh)
            node.set_transform(spring.transform(0))
            for end, positions in (("a", spring.starts), ("b", spring.ends)):
                sphere = root["anchors"][f"{spring.name}.{end}"]
                sphere.set_object(mg.Sphere(1.6 * spring.wire_radius + 0.004), mg.MeshPhongMaterial(color=ANCHOR_COLOR))
                sphere.set_transform(placement(np.eye(3), positions[0]))
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
        """The meshcat animation of the path: arm, springs (stretch and colour), anchors, regions.

        ``helix_objects`` maps each spring to the uuid of its helix mesh, which the colour
        track addresses (three.js finds a node's child object by name or uuid).
        """
        animation = _Animation(default_framerate=self.fps)
        model, data = arm.model, arm.model.createData()
        visual_model, visual_data = arm.visual_model, arm.visual_model.createData()
        names = [arm.getViewerNodeName(geometry, pin.GeometryType.VISUAL) for geometry in visual_model.geometryObjects]
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
                                      list(self.color_scale.rgb(spring.tensions[frame])))
                    root["anchors"][f"{spring.name}.a"].set_transform(placement(np.eye(3), spring.starts[frame]))
                    root["anchors"][f"{spring.name}.b"].set_transform(placement(np.eye(3), spring.ends[frame]))
                for region in self.regions:
                    root["regions"][f"{region.spring}.{region.end}"].set_transform(region.placements[frame])
        return animation

    def _arm_visualizer(self, visualizer):
        from pinocchio.visualize import MeshcatVisualizer

        model = self.mechanism.model
        visual_model = visual_geometry(self.mechanism)
        if visual_model is None or visual_model.ngeoms == 0:
            visual_model = stick_figure(model)
        arm = MeshcatVisualizer(model, None, visual_model)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # pinocchio warns about geometry it cannot show; the rest is drawn
            arm.initViewer(viewer=visualizer)
            arm.loadViewerModel(rootNodeName="pinocchio")
        return arm

    def _set_camera(self, visualizer, arm) -> None:
        """Look at the middle of everything that moves, from the side that shows the motion best."""
        model, data = arm.model, arm.model.createData()
        points = [spring.starts for spring in self.springs] + [spring.ends for spring in self.springs]
        for q in self.configurations[:: max(self.size // 40, 1)]:
            pin.forwardKinematics(model, data, q)
            points.append(np.array([data.oMi[j].translation for j in range(model.njoints)]))
            pin.updateFramePlacements(model, data)
            points.append(np.array([data.oMf[f].translation for f in range(model.nframes)]))
        cloud = np.vstack(points)
        lower, upper = cloud.min(axis=0), cloud.max(axis=0)
        center = (lower + upper) / 2
        radius = max(float(np.max(np.linalg.norm(cloud - center, axis=1))), 0.15)   # [m]
        # a planar arm is seen square-on (along the normal of its plane), any other from an oblique corner
        _, spread, axes = np.linalg.svd(cloud - cloud.mean(axis=0), full_matrices=False)
        if spread[-1] < 0.2 * spread[-2]:
            normal = axes[-1] if axes[-1] @ np.array([0.3, -1.0, 0.0]) >= 0 else -axes[-1]
            direction = normal + np.array([0.35, -0.25, 0.45])
        else:
            direction = np.array([1.0, -1.3, 0.8])
        direction /= np.linalg.norm(direction)
        offset = 1.7 * radius * direction                                   # [m] camera from the target
        visualizer["/Cameras/default"].set_transform(placement(np.eye(3), center))
        # the camera node is rotated by +90° about x (meshcat's y-up convention): world (x, y, z) = rotated (x, z, -y)
        visualizer["/Cameras/default/rotated/<object>"].set_property("position", [offset[0], offset[2], -offset[1]])

    # ---------------------------------------------------------------- exports
    def html(self, animate: bool = True, autoplay: bool = True, legend: bool = True) -> str:
        """Self-contained HTML page of the scene (meshcat's static page plus the colour legend)."""
        recorder = SceneRecorder()
        visualizer = meshcat.Visualizer(window=recorder)
        self.draw(visualizer, animate=animate, autoplay=autoplay)
        page = visualizer.static_html()
        if legend:
            page = _insert_before_body_end(page, self.color_scale.legend_html(self.compression))
        return page


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
    """The self-contained HTML page of a design's scene (no server, no network)."""
    return DesignScene(result, joint_values, **options).html(animate=animate, autoplay=autoplay, legend=legend)


def save_scene_html(result, path: str | Path, **options) -> Path:
    """Write :func:`scene_html` to ``path`` (folders are created)."""
    return write_text_atomic(path, scene_html(result, **options))


def show(result, joint_values=None, static: bool = False, open_browser: bool = False, port: int | None = None,
         **options):
    """Show a design in meshcat.

    ``static=True`` returns a :class:`StaticScene` (inline in Jupyter, no server). Otherwise
    the scene is drawn on the session's local server (:func:`local_server`, 127.0.0.1 only)
    and a :class:`LiveScene` with its URL is returned.
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
