"""The Meshcat scene of a design (:class:`DesignScene`): the arm, its springs drawn as helices, and an animation.

What is drawn (all lengths in m, forces in N):

- the arm, through Pinocchio's ``MeshcatVisualizer`` with the URDF's visual geometry
  (meshes of example-robot-data included); a mechanism without visual geometry is drawn
  as a stick figure of its joints, links and centres of mass (:mod:`springbalance.viz.arm`);
- every spring as a **helix** (a tube along a helical centre line with a straight hook at
  each end, :mod:`springbalance.viz.helix`) from its end ``x_a`` to its end ``x_b``
  (:class:`~springbalance.viz.tracks.SpringTrack`), coloured by its tension ``F(L)`` on a
  :class:`~springbalance.viz.colors.ColorScale` (warm colours for tension, greens for compression)
  that the static page shows as a legend; the legend's scale reaches into compression ("negative:
  pushing") only when some spring really pushes (tension below zero) in some frame of the animation;
- with a **clearance margin** ``m`` [m] (the ``margin`` argument, else the design problem's
  ``clearance.margin``) and a URDF with ``<collision>`` elements: in every frame where a
  spring's capsule (radius: half its coil's outer diameter, else the problem's
  ``clearance.radius``, else 0.01 m; see :func:`springbalance.model.collision.capsule_radius`)
  comes closer than ``m`` (or touches: distance ≤ 0) to the collision geometry of any body
  but its own two anchor bodies (the rule of :mod:`springbalance.results.clearance`), the
  spring is drawn solid red (:data:`~springbalance.viz.colors.CLEARANCE_COLOR`) instead of
  its tension colour, a red marker sphere sits at its closest point to the arm in those frames
  (:mod:`springbalance.viz.markers`),
  and the legend names it ("below clearance margin (m mm)"); the signed
  distances [m] per frame are :attr:`SpringTrack.clearance`. Without collision geometry the
  springs keep their tension colours;
- springs named in ``flagged`` (the report passes the springs that run inside their own link
  beyond their anchor, :mod:`springbalance.results.own_link`) solid red in every frame, named in
  the legend with the reason, with a red marker where the spring runs inside its own link in a frame
  (:mod:`springbalance.viz.own_link_marks`);
- the **name of each spring** as an HTML label that follows a point just above the middle of the
  spring and is placed so that no two labels overlap (:mod:`springbalance.viz.overlay`);
- a small sphere at each anchor, and the free region of each anchor of the original
  problem (box, segment or plane rectangle of :mod:`springbalance.springs.params`) as a
  thin wireframe fixed to its body (:mod:`springbalance.viz.regions`), hidden until the page's
  "anchor regions" checkbox shows it;
- the arm's mesh files decimated, one part per colour (:mod:`springbalance.viz.arm_meshes`), sent
  once and moved by the animation;
- a force along a fixed direction (docs/model.md §3.11) as an arrow from its anchor along its push
  (:mod:`springbalance.viz.arrows`);
- the parallelograms that realise the mechanism's pseudo-bases, as rods (:mod:`springbalance.viz.parallelograms`);
- an animation along an ordered path of poses (by default a sweep of each joint in turn,
  :func:`springbalance.model.sweeps.animation_path`), meshcat's play/pause/time controls and a pose slider.

The camera shows the arm and its springs at the first pose as large as the view allows while every pose
of the path stays in view, from a three-quarter view, with the floor grid under the arm
(:mod:`springbalance.viz.framing`, :mod:`springbalance.viz.camera`).
The end points come from the workspace kinematics (:mod:`springbalance.model.kinematics`), lengths
and tensions from the design's own evaluation (``EvaluatedDesign.evaluate_on``).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from springbalance.deprecation import warn_deprecated
from springbalance.design.evaluated import EvaluatedDesign
from springbalance.errors import InputError
from springbalance.model import sweeps
from springbalance.model.workspace import Workspace
from springbalance.viz.arm import stick_figure, visual_geometry
from springbalance.viz.arm_meshes import draw_mesh_file, drawable
from springbalance.viz.arrows import animate_arrow, arrows_legend_html, draw_arrows, force_arrows
from springbalance.viz.camera import bounding_spheres, place_camera
from springbalance.viz.colors import CLEARANCE_COLOR, CLEARANCE_RGB, ColorScale
from springbalance.viz.framing import best_view, view_points
from springbalance.viz.helix import HelixStyle, placement
from springbalance.viz.markers import MARKER_RADIUS, animate_marker, draw_marker  # noqa: F401 (MARKER_RADIUS: old home)
from springbalance.viz.meshcat_glue import ROOT, insert_before_body_end, meshcat_classes
from springbalance.viz.meshcat_import import import_meshcat
from springbalance.viz.overlay import overlay_html
from springbalance.viz.own_link_marks import add_own_link
from springbalance.viz.parallelograms import draw_parallelograms, parallelogram_rods, place_parallelograms
from springbalance.viz.pose_paths import scene_path
from springbalance.viz.pose_slider import scene_slider_html
from springbalance.viz.recorder import SceneRecorder
from springbalance.viz.regions import REGION_COLOR, RegionShape, anchor_regions, region_geometry
from springbalance.viz.rods import add_brackets, animate_rods, draw_rods
from springbalance.viz.tracks import SpringTrack, add_clearances, spring_tracks

ANCHOR_COLOR = 0x333333
#: Side of a label's square sprite (live view) as a fraction of the camera's distance from what it frames.
LABEL_SIZE = 0.22
#: the helix drawn when no style is given (frozen: one instance serves every scene)
DEFAULT_HELIX = HelixStyle()


class DesignScene:
    """Everything needed to draw a design along an ordered path of poses.

    Args:
        design (EvaluatedDesign): the design (:class:`~springbalance.design.evaluated.EvaluatedDesign`,
            such as a :class:`~springbalance.results.result.DesignResult`).
        joint_values (numpy.ndarray | None): the path (N×nv joint coordinates [rad or m]); default
            :func:`~springbalance.model.sweeps.animation_path` (a sweep of each joint).
        frames_per_joint: frames of each joint's sweep in the default path.
        style: :class:`HelixStyle`.
        fps: frames per second of the animation.
        margin: clearance margin [m] (≥ 0): a spring is drawn red in the frames where its
            capsule is closer than this to the arm's collision geometry (see the module
            documentation). Default: ``design.problem.clearance.margin`` when the problem has a
            clearance, else no clearance is drawn. Ignored (no error) when the URDF has no
            ``<collision>`` elements; :attr:`clearance_note` then says why.
        flagged: springs drawn red in every frame, by name, with why (one line for the legend), such
            as the springs that run inside their own link (:mod:`springbalance.results.own_link`).
        poses: instead of ``joint_values``: "sweep", "workspace" or "worst[:N]" (:mod:`springbalance.viz.pose_paths`).

    Attributes:
        design: the design drawn.
        springs: one :class:`SpringTrack` per drawn (two-point) spring.
        skipped: the springs left out of the drawing (torsional springs), by name.
        regions: one :class:`~springbalance.viz.regions.RegionShape` per anchor with a free region.
        color_scale: the :class:`ColorScale` of the tensions [N].
        compression: True when some drawn spring pushes (negative tension) in some frame.
        margin: the clearance margin [m], or None.
        clearance_note: why no clearance is drawn although a margin is set (else None).
        camera_center, camera_radius: a sphere [m] about the camera's target that holds the arm and its
            springs over the whole path;
        camera_target, camera_position: where the camera looks (the middle of the framed view, which
            the scene is moved to: meshcat orbits about it) and where it stands (world, [m]);
        camera_share: the share of the view's width and height the first pose covers. The five are set
            by :meth:`draw` (:func:`~springbalance.viz.framing.best_view`).
    """

    def __init__(
        self,
        design: EvaluatedDesign,
        joint_values: npt.ArrayLike | None = None,
        frames_per_joint: int = 48,
        style: HelixStyle = DEFAULT_HELIX,
        fps: int = 30,
        margin: float | None = None,
        flagged: dict[str, str] | None = None,
        poses: str | None = None,
    ) -> None:
        self.design = design
        joint_values, self.path_title = scene_path(design, joint_values, poses, frames_per_joint)  # slider's caption
        mechanism = design.problem.mechanism
        self.mechanism = mechanism
        if joint_values is None:
            joint_values = sweeps.animation_path(design, frames_per_joint)
        self.workspace = Workspace.from_array(mechanism, joint_values, ordered=True)
        self.joint_values = self.workspace.joint_values
        self.configurations = self.workspace.configurations
        self.fps = int(fps)
        self.style = style
        self.evaluation = design.evaluate_on(self.workspace)  # lengths and tensions from the model
        kinematics = self.workspace.kinematics()
        self.springs: list[SpringTrack]
        self.springs, self._records, columns = spring_tracks(
            design, self.evaluation.lengths, self.evaluation.tensions, kinematics, style
        )
        #: forces along a fixed direction, drawn as arrows (:mod:`springbalance.viz.arrows`)
        self.arrows, drawn = force_arrows(design, self.evaluation.tensions, kinematics)
        #: the springs left out of the drawing (torsional springs), by name
        self.skipped = [record["name"] for column, record in enumerate(design.springs) if column not in columns + drawn]
        path_tensions = self.evaluation.tensions[:, columns]
        design_tensions = design.evaluation.tensions[:, columns]
        self.color_scale = ColorScale.for_tensions(path_tensions, design_tensions)
        # the legend's compression half is for springs that push in the animation, not for laws that could
        self.compression = bool(np.any(self.color_scale.pushes(path_tensions)))
        self.regions: list[RegionShape] = anchor_regions(design.problem.springs, kinematics, self.size)
        #: the rods of the parallelograms realising the pseudo-bases (:mod:`springbalance.viz.parallelograms`)
        self.parallelograms = parallelogram_rods(mechanism, self.configurations)
        self.flagged = dict(flagged or {})
        self.margin, self.clearance_note = self._margin(margin), None
        if self.margin is not None:
            radius = getattr(getattr(design.problem, "clearance", None), "radius", None)
            self.clearance_note = add_clearances(
                self.springs, self._records, mechanism, self.configurations, self.margin, radius
            )
        add_own_link(self.springs, self._records, mechanism, self.configurations, self.flagged)  # their markers
        add_brackets(self.springs, self._records, mechanism, kinematics, self.configurations)  # off their links
        self.camera_center: np.ndarray | None = None
        self.camera_radius: float | None = None
        self.camera_target: np.ndarray | None = None
        self.camera_position: np.ndarray | None = None
        self.camera_share: tuple[float, float] | None = None

    @property
    def result(self) -> EvaluatedDesign:
        """Deprecated alias of :attr:`design`."""
        warn_deprecated("DesignScene.result", "DesignScene.design")
        return self.design

    def _margin(self, margin: float | None) -> float | None:
        """The margin [m] asked for, else the problem's clearance margin (``DesignProblem.clearance``), else None."""
        clearance = getattr(self.design.problem, "clearance", None)
        if margin is None and clearance is not None:
            margin = getattr(clearance, "margin", None)
        if margin is None:
            return None
        if (
            isinstance(margin, bool)
            or not isinstance(margin, (int, float, np.integer, np.floating))
            or not (np.isfinite(margin) and margin >= 0)
        ):
            raise InputError(f"clearance margin must be a finite number ≥ 0 [m], got {margin!r}")
        return float(margin)

    @property
    def clearance_violated(self) -> bool:
        """True when some spring is below the clearance margin in some frame (it is drawn red)."""
        return any(track.below_margin is not None and bool(np.any(track.below_margin)) for track in self.springs)

    def rgb(self, spring: SpringTrack, frame: int) -> tuple[float, float, float]:
        """Colour (RGB in [0, 1]) of ``spring`` at pose ``frame``: red below the clearance margin (or
        when flagged), else the colour of its tension."""
        if self.red(spring, frame):
            return CLEARANCE_RGB
        return self.color_scale.rgb(spring.tensions[frame])

    def hex(self, spring: SpringTrack, frame: int) -> int:
        """:meth:`rgb` as the 0xRRGGBB integer that meshcat materials take."""
        if self.red(spring, frame):
            return CLEARANCE_COLOR
        return self.color_scale.hex(spring.tensions[frame])

    def red(self, spring: SpringTrack, frame: int) -> bool:
        """True when ``spring`` is drawn red at pose ``frame``: below the clearance margin there, or flagged."""
        below = spring.below_margin is not None and bool(spring.below_margin[frame])
        return below or spring.name in self.flagged

    def problems(self) -> list[str]:
        """One line per spring drawn red: the frames below the clearance margin, and why it is flagged; one per
        bracket drawn red: the frames where it passes through another link (:mod:`springbalance.viz.rods`)."""
        lines = []
        for spring in self.springs:
            if spring.below_margin is not None and np.any(spring.below_margin):
                count = int(np.count_nonzero(spring.below_margin))
                lines.append(f"{spring.name}: below the margin in {count} of {self.size} frames")
            if spring.name in self.flagged:
                lines.append(f"{spring.name}: {self.flagged[spring.name]}")
            for end, through in (spring.brackets_through or {}).items():
                if np.any(through):
                    count = int(np.count_nonzero(through))
                    lines.append(f"{spring.name}.{end}'s bracket: through a link in {count} of {self.size} frames")
        return lines

    def legend_html(self, position: str = "fixed") -> str:
        """The colour legend of the scene (see :meth:`ColorScale.legend_html`): the tension scale, its
        compression half only when some spring pushes, the clearance entry only when some spring is
        below the margin, and the name of every spring drawn red (:meth:`problems`)."""
        if not self.springs:  # nothing on the tension scale: what is drawn instead
            return arrows_legend_html([arrow.name for arrow in self.arrows], self.skipped, position)
        return self.color_scale.legend_html(
            self.compression,
            position=position,
            clearance_margin=self.margin if self.clearance_violated else None,
            flagged=self.problems(),
        )

    @property
    def size(self) -> int:
        """Number of poses (animation frames)."""
        return self.workspace.size

    # ---------------------------------------------------------------- drawing
    def draw(self, visualizer: Any, animate: bool = True, autoplay: bool = True, sprites: bool = False) -> None:
        """Draw the scene on a ``meshcat.Visualizer`` (live or recording). ``sprites``: also the name labels as
        text sprites in the scene, for meshcat's own viewer (they may overlap); the scene's pages, static and
        live, draw them in HTML, apart (:meth:`labels`, :mod:`springbalance.viz.overlay`)."""
        classes = meshcat_classes()
        arm = self._arm_visualizer(visualizer)
        arm.display(self.configurations[0])
        visualizer["/Background"].set_property("top_color", [1.0, 1.0, 1.0])
        visualizer["/Background"].set_property("bottom_color", [0.8, 0.83, 0.88])
        visualizer["/Axes"].set_property("visible", False)
        self._set_camera(visualizer, arm)

        root = visualizer[ROOT]
        helix_objects = self._draw_springs(root, sprites)
        draw_arrows(root, self.arrows)
        self._draw_regions(root)
        draw_parallelograms(root, self.parallelograms)
        if animate and self.size > 1:
            visualizer.window.send(
                classes.SetAnimation(
                    self.animation(visualizer, arm, helix_objects), play=autoplay, repetitions=float("inf")
                )
            )

    def _draw_springs(self, root: Any, sprites: bool = True) -> dict[str, str]:
        """Draw each spring at the first pose below ``root``: its helix, the node its name label follows
        (a text sprite there with ``sprites``), its clearance marker, anchor spheres, cable and brackets. Returns
        the uuid of each spring's helix mesh by spring name."""
        mg = import_meshcat().geometry
        if self.camera_position is None or self.camera_target is None:
            raise RuntimeError("the springs are drawn after the camera is placed (DesignScene.draw)")
        label_size = LABEL_SIZE * float(np.linalg.norm(self.camera_position - self.camera_target))  # [m], a side
        helix_objects = {}
        for spring in self.springs:
            vertices, faces = spring.mesh()
            node = root["springs"][spring.name]
            mesh = mg.Mesh(
                mg.TriangularMeshGeometry(vertices, faces),
                mg.MeshPhongMaterial(color=self.hex(spring, 0), shininess=40),
            )
            helix_objects[spring.name] = mesh.uuid
            node.set_object(mesh)
            node.set_transform(spring.transform(0))
            label = root["labels"][spring.name]  # the HTML label follows this node (springbalance.viz.overlay)
            if sprites:
                label.set_object(meshcat_classes().TextSprite(spring.name, label_size))
            label.set_transform(placement(np.eye(3), self.label_positions(spring)[0]))
            draw_marker(root, spring, mg)
            for end, positions in spring.points_by_end().items():
                sphere = root["anchors"][f"{spring.name}.{end}"]
                sphere.set_object(mg.Sphere(1.6 * spring.wire_radius + 0.004), mg.MeshPhongMaterial(color=ANCHOR_COLOR))
                sphere.set_transform(placement(np.eye(3), positions[0]))
            draw_rods(root, spring, mg)
        return helix_objects

    def _draw_regions(self, root: Any) -> None:
        """Draw each anchor's free region at the first pose below ``root`` as a thin wireframe (its
        edges), hidden until the page's control (or meshcat's) shows ``regions``."""
        mg = import_meshcat().geometry
        root["regions"].set_property("visible", False)
        for region in self.regions:
            node = root["regions"][f"{region.spring}.{region.end}"]
            _, edges = region_geometry(region)
            node["edges"].set_object(
                mg.LineSegments(mg.PointsGeometry(edges.T), mg.LineBasicMaterial(color=REGION_COLOR, linewidth=1))
            )
            node.set_transform(region.placements[0])

    def animation(self, visualizer: Any, arm: Any, helix_objects: dict[str, str]) -> Any:
        """The meshcat animation of the path: arm, springs (stretch and colour), name labels, anchors, regions.

        ``helix_objects`` maps each spring to the uuid of its helix mesh, which the colour
        track addresses (three.js finds a node's child object by name or uuid).
        """
        animation = meshcat_classes().Animation(default_framerate=self.fps)
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
                    self._animate_spring(root, spring, frame, helix_objects[spring.name], labels[spring.name])
                for arrow in self.arrows:
                    animate_arrow(root, arrow, frame)
                for region in self.regions:
                    root["regions"][f"{region.spring}.{region.end}"].set_transform(region.placements[frame])
                place_parallelograms(root, self.parallelograms, frame)
        return animation

    def _animate_spring(self, root: Any, spring: SpringTrack, frame: int, helix: str, labels: np.ndarray) -> None:
        """Key frame ``frame`` of ``spring`` below ``root`` (a frame of the animation): helix placement,
        length and colour (object ``helix``), name label (at ``labels[frame]``), anchors and cable."""
        node = root["springs"][spring.name]
        node.set_transform(spring.rigid_transform(frame))
        node.set_property("scale", "vector3", [1.0, 1.0, spring.length(frame)])
        node.set_property(f"{helix}.material.color", "color", list(self.rgb(spring, frame)))
        root["labels"][spring.name].set_property("position", "vector3", [float(v) for v in labels[frame]])
        animate_marker(root, spring, frame)
        for end, positions in spring.points_by_end().items():
            point = [float(v) for v in positions[frame]]
            root["anchors"][f"{spring.name}.{end}"].set_property("position", "vector3", point)
        animate_rods(root, spring, frame)

    def _visual_model(self) -> pin.GeometryModel:
        """The arm's visual geometry: the URDF's, or a stick figure when it has none."""
        visual_model = visual_geometry(self.mechanism)
        if visual_model is None or visual_model.ngeoms == 0:
            visual_model = stick_figure(self.mechanism.model)
        return visual_model

    def _arm_visualizer(self, visualizer: Any) -> Any:
        import_meshcat()  # first, under its warnings filter: pinocchio.visualize imports meshcat
        from pinocchio.visualize import MeshcatVisualizer

        arm = MeshcatVisualizer(self.mechanism.model, None, self._visual_model())
        load_default = arm.loadViewerGeometryObject

        def load(geometry_object: Any, geometry_type: Any, color: Any = None) -> None:
            """Mesh files as decimated parts (:mod:`springbalance.viz.arm_meshes`), the rest as Pinocchio does."""
            if not drawable(geometry_object):
                return load_default(geometry_object, geometry_type, color)
            node = arm.viewer[arm.getViewerNodeName(geometry_object, geometry_type)]
            return draw_mesh_file(node, geometry_object, import_meshcat().geometry)

        arm.loadViewerGeometryObject = load
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # pinocchio warns about geometry it cannot show; the rest is drawn
            arm.initViewer(viewer=visualizer)
            arm.loadViewerModel(rootNodeName="pinocchio")
        return arm

    def label_positions(self, spring: SpringTrack) -> np.ndarray:
        """Where the name label of ``spring`` sits per pose (N×3) [m]: just above its middle (world +z,
        by its coil radius plus its wire), so the text stands over the helix."""
        return spring.midpoints() + np.array([0.0, 0.0, spring.coil_radius + spring.wire_radius + 0.004])

    def bounding_spheres(self, visual_model: pin.GeometryModel | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Centres (K×3) [m] and radii (K) [m] of spheres that hold, over every frame, what is drawn
        (:func:`springbalance.viz.camera.bounding_spheres`); ``visual_model``: the arm's links (default:
        the URDF's visual geometry, or the stick figure)."""
        if visual_model is None:
            visual_model = self._visual_model()
        return bounding_spheres(self.springs, self.regions, self.mechanism.model, visual_model, self.configurations)

    def _set_camera(self, visualizer: Any, arm: Any) -> None:
        """Frame the arm and its springs (not the hidden anchor regions): the first pose as large as the view
        allows with every pose of the path in view, from a three-quarter view (:func:`~springbalance.viz.framing.best_view`);
        the grid under the arm, or on the mechanism's floor when it has one (the table its springs keep clear of)."""
        model = self.mechanism.model
        motion = view_points(self.springs, model, arm.visual_model, self.configurations)
        view = best_view(motion, view_points(self.springs, model, arm.visual_model, self.configurations, slice(0, 1)))
        self.camera_target, self.camera_position, self.camera_share = view
        self.camera_center = view.target
        self.camera_radius = float(np.max(np.linalg.norm(motion - view.target, axis=1)))
        floor = self.mechanism.floor if self.mechanism.floor is not None else float(motion[:, 2].min())
        place_camera(visualizer, view.position, view.target, floor, self.camera_radius)

    # ---------------------------------------------------------------- exports
    def labels(self) -> str:
        """The pages' name labels, placed apart, and the anchor regions' checkbox (:func:`~springbalance.viz.overlay.overlay_html`;
        a spring drawn red in some frame has a red label)."""
        red = [(spring.name, any(self.red(spring, f) for f in range(self.size))) for spring in self.springs]
        return overlay_html(red, bool(self.regions))

    def html(self, animate: bool = True, autoplay: bool = True, legend: bool = True) -> str:
        """Self-contained HTML page of the scene: meshcat's static page, the name labels and the regions'
        checkbox (:func:`~springbalance.viz.overlay.overlay_html`), the pose slider and the colour legend."""
        recorder = SceneRecorder()
        visualizer = import_meshcat().Visualizer(window=recorder)
        self.draw(visualizer, animate=animate, autoplay=autoplay, sprites=False)
        page = visualizer.static_html()
        page = insert_before_body_end(page, self.labels() + scene_slider_html(self, animate))
        if legend:
            page = insert_before_body_end(page, self.legend_html())
        return page
