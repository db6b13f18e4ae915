"""Meshcat scene of a design: the entry points, and every name of the scene's modules.

- :func:`scene_html` / :func:`save_scene_html`: the self-contained HTML page of a design's scene.
  The scene is recorded in memory (:mod:`springbalance.viz.recorder`) and meshcat's own server code
  gives its self-contained page (scripts and meshes inlined, no network), without opening a socket.
- :func:`show`: the scene on the session's live meshcat server, which runs in a child process and
  listens on 127.0.0.1 only (:mod:`springbalance.viz.live`, :mod:`springbalance.viz.server`), or a
  :class:`StaticScene` (inline in Jupyter, no server).

What is drawn is :class:`~springbalance.viz.design_scene.DesignScene`'s business; the scene's parts:

- :mod:`springbalance.viz.tracks`: each spring along the path (:class:`SpringTrack`), its clearance;
- :mod:`springbalance.viz.regions`: the free region of each anchor (:class:`RegionShape`);
- :mod:`springbalance.viz.camera`: where the camera stands (:func:`camera_distance`);
- :mod:`springbalance.viz.meshcat_glue`: text sprites and the animation's meshcat subclasses;
- :mod:`springbalance.viz.meshcat_import`: meshcat itself, imported on first use only.

Every name this module had before it was split is still importable from it. Nothing here is
imported by the core modules; data flows design → scene.
"""

from __future__ import annotations

import html
from pathlib import Path
from typing import Any

import numpy.typing as npt

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.files import write_text_atomic
from springbalance.viz.camera import CAMERA_FILL, CAMERA_FOV, camera_distance
from springbalance.viz.colors import CLEARANCE_COLOR, CLEARANCE_RGB, ColorScale
from springbalance.viz.design_scene import ANCHOR_COLOR, LABEL_SIZE, DesignScene
from springbalance.viz.helix import HelixStyle, helix_centerline, helix_tube, placement, spring_rotation

# the private names below are the old module's, kept importable from here for one release
from springbalance.viz.live import LiveScene, local_server, publish_scene
from springbalance.viz.meshcat_glue import LABEL_FONT_SIZE, ROOT, meshcat_classes
from springbalance.viz.meshcat_glue import insert_before_body_end as _insert_before_body_end  # noqa: F401 (old name)
from springbalance.viz.meshcat_import import import_meshcat
from springbalance.viz.recorder import SceneRecorder
from springbalance.viz.regions import _BOX_EDGES, REGION_COLOR, REGION_OPACITY, RegionShape, _box_mesh  # noqa: F401
from springbalance.viz.regions import region_corners as _region_corners  # noqa: F401 (old name)
from springbalance.viz.regions import region_geometry as _region_geometry  # noqa: F401 (old name)
from springbalance.viz.regions import region_points as _region_points  # noqa: F401 (old name)
from springbalance.viz.regions import spring_anchors as _anchors  # noqa: F401 (old name)
from springbalance.viz.rods import CABLE_COLOR, CABLE_RADIUS
from springbalance.viz.tracks import SpringTrack

__all__ = [
    "ANCHOR_COLOR",
    "CABLE_COLOR",
    "CABLE_RADIUS",
    "CAMERA_FILL",
    "CAMERA_FOV",
    "CLEARANCE_COLOR",
    "CLEARANCE_RGB",
    "LABEL_FONT_SIZE",
    "LABEL_SIZE",
    "REGION_COLOR",
    "REGION_OPACITY",
    "ROOT",
    "ColorScale",
    "DesignScene",
    "HelixStyle",
    "LiveScene",
    "RegionShape",
    "SceneRecorder",
    "SpringTrack",
    "StaticScene",
    "camera_distance",
    "helix_centerline",
    "helix_tube",
    "local_server",
    "placement",
    "save_scene_html",
    "scene_html",
    "show",
    "spring_rotation",
]

#: names made on first use, when meshcat is imported (see :func:`__getattr__`)
_LAZY = {
    "_TextTexture": "TextTexture",
    "_SpriteMaterial": "SpriteMaterial",
    "_TextSprite": "TextSprite",
    "_Animation": "Animation",
    "_SetAnimation": "SetAnimation",
}


def __getattr__(name: str) -> Any:
    """meshcat (``meshcat``, ``mg``) and the subclasses of its classes (``_TextSprite``, ``_Animation`` …),
    imported when first asked for: importing this module does not import meshcat."""
    if name == "meshcat":
        return import_meshcat()
    if name == "mg":
        return import_meshcat().geometry
    if name in _LAZY:
        return getattr(meshcat_classes(), _LAZY[name])
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class StaticScene:
    """A self-contained scene page; in Jupyter it shows inline without any server."""

    def __init__(self, page: str) -> None:
        self.page = page

    def save(self, path: str | Path) -> Path:
        """Write the page to ``path`` (folders are created); returns the path."""
        return write_text_atomic(path, self.page)

    def _repr_html_(self) -> str:
        return (
            f'<iframe srcdoc="{html.escape(self.page, quote=True)}" style="width:100%;height:480px;border:none">'
            "</iframe>"
        )

    def __repr__(self) -> str:
        return f"StaticScene({len(self.page)} characters)"


def scene_html(
    design: EvaluatedDesign,
    joint_values: npt.ArrayLike | None = None,
    animate: bool = True,
    autoplay: bool = True,
    legend: bool = True,
    **options: Any,
) -> str:
    """The self-contained HTML page of a design's scene (no server, no network); ``options`` go to
    :class:`DesignScene` (``frames_per_joint``, ``style``, ``fps``, ``margin`` [m])."""
    return DesignScene(design, joint_values, **options).html(animate=animate, autoplay=autoplay, legend=legend)


def save_scene_html(design: EvaluatedDesign, path: str | Path, **options: Any) -> Path:
    """Write :func:`scene_html` to ``path`` (folders are created)."""
    return write_text_atomic(path, scene_html(design, **options))


def show(
    design: EvaluatedDesign,
    joint_values: npt.ArrayLike | None = None,
    static: bool = False,
    open_browser: bool = False,
    port: int | None = None,
    **options: Any,
) -> LiveScene | StaticScene:
    """Show a design in meshcat.

    ``static=True`` returns a :class:`StaticScene` (inline in Jupyter, no server). Otherwise
    the scene is drawn on the session's local server (:func:`local_server`, 127.0.0.1 only)
    and a :class:`LiveScene` with its URL is returned (the scene's page there: meshcat's viewer with the legend
    and the pose slider). ``options`` go to :class:`DesignScene`
    (``frames_per_joint``, ``style``, ``fps``, ``margin`` [m]).
    """
    scene = DesignScene(design, joint_values, **options)
    if static:
        return StaticScene(scene.html())
    server = local_server(port)
    visualizer = server.visualizer()
    visualizer.delete()
    scene.draw(visualizer)
    page_url = publish_scene(server, scene)
    if open_browser:
        import webbrowser

        webbrowser.open(page_url, new=2)
    return LiveScene(scene, server, visualizer, page_url)
