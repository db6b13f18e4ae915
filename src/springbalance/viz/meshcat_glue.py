"""What springbalance adds to meshcat: text sprites (the springs' name labels), an animation with
colour tracks of a node's object, and the command that keeps that animation after the objects.

meshcat is imported on first use (:func:`~springbalance.viz.meshcat_import.import_meshcat`), so the
subclasses of its classes are made once, by :func:`meshcat_classes`, when a scene is first drawn.
"""

from __future__ import annotations

import functools
from types import ModuleType
from typing import Any, NamedTuple

import numpy as np
import umsgpack

from springbalance.viz.meshcat_import import import_meshcat

#: Meshcat path (below ``/meshcat``) of everything springbalance draws besides the arm.
ROOT = "springbalance"
#: Height of a spring's name label [px] on its 256 px canvas texture (smaller for long names).
LABEL_FONT_SIZE = 40


class MeshcatClasses(NamedTuple):
    """springbalance's subclasses of meshcat classes (see :func:`meshcat_classes`)."""

    TextTexture: type
    SpriteMaterial: type
    TextSprite: type
    Animation: type
    SetAnimation: type


@functools.cache
def meshcat_classes() -> MeshcatClasses:
    """The subclasses of meshcat's classes, made once (meshcat is imported by the first call):

    - ``TextTexture``: meshcat's ``_text`` texture, ``text`` centred on a 256×256 px canvas;
    - ``SpriteMaterial``: a three.js ``SpriteMaterial`` showing a texture over everything;
    - ``TextSprite(text, size)``: a text label, a square sprite of side ``size`` [m] facing the camera;
    - ``Animation``: meshcat's animation plus tracks of a property of a node's object;
    - ``SetAnimation``: meshcat's set_animation command, replayed after the objects.
    """
    meshcat = import_meshcat()
    texture = _text_texture(meshcat.geometry)
    material = _sprite_material(meshcat.geometry)
    return MeshcatClasses(
        texture,
        material,
        _text_sprite(meshcat.geometry, texture, material),
        _animation(meshcat.animation),
        _set_animation(meshcat.commands),
    )


def _text_texture(mg: ModuleType) -> type:
    class _TextTexture(mg.Texture):  # type: ignore[name-defined]  # meshcat: no stubs, lazy import
        """meshcat's ``_text`` texture: the viewer draws ``text`` centred on a 256×256 px canvas
        (``font_size`` px, smaller when the text is wider than the canvas)."""

        def __init__(self, text: str, font_size: int = LABEL_FONT_SIZE, font_face: str = "sans-serif") -> None:
            super().__init__()
            self.text, self.font_size, self.font_face = str(text), int(font_size), font_face

        def lower(self, object_data: dict[str, Any]) -> dict[str, Any]:
            return {
                "uuid": self.uuid,
                "type": "_text",
                "text": self.text,
                "font_size": self.font_size,
                "font_face": self.font_face,
            }

    return _TextTexture


def _sprite_material(mg: ModuleType) -> type:
    class _SpriteMaterial(mg.Material):  # type: ignore[name-defined]  # meshcat: no stubs, lazy import
        """three.js ``SpriteMaterial`` showing a texture, drawn over everything (no depth test)."""

        def __init__(self, texture: Any) -> None:
            super().__init__()
            self.texture = texture

        def lower(self, object_data: dict[str, Any]) -> dict[str, Any]:
            return {
                "uuid": self.uuid,
                "type": "SpriteMaterial",
                "color": 0xFFFFFF,
                "transparent": True,
                "depthTest": False,
                "depthWrite": False,
                "sizeAttenuation": True,
                "map": self.texture.lower_in_object(object_data),
            }

    return _SpriteMaterial


def _text_sprite(mg: ModuleType, texture_class: type, material_class: type) -> type:
    class _TextSprite(mg.Object):  # type: ignore[name-defined]  # meshcat: no stubs, lazy import
        """A text label: a three.js ``Sprite`` (a square that always faces the camera) of side ``size``
        [m], centred on its node, with ``text`` on it (meshcat's ``_text`` texture)."""

        def __init__(self, text: str, size: float) -> None:
            super().__init__(None, material_class(texture_class(text)))
            self.text, self.size = text, float(size)

        def lower(self) -> dict[str, Any]:
            data: dict[str, Any] = {
                "metadata": {"version": 4.5, "type": "Object"},
                "geometries": [],
                "materials": [],
                "textures": [],
                "images": [],
                "object": {
                    "uuid": self.uuid,
                    "type": "Sprite",
                    "name": self.text,
                    "material": self.material.uuid,
                    "matrix": list(np.diag([self.size, self.size, 1.0, 1.0]).flatten()),
                },
            }
            self.material.lower_in_object(data)
            return data

    return _TextSprite


def _animation(animation_module: ModuleType) -> type:
    class _Animation(animation_module.Animation):  # type: ignore[name-defined]  # meshcat: no stubs, lazy import
        """meshcat's Animation, plus tracks of a property of a node's object (``<uuid>.material.color``).

        meshcat names every track ``.<property>``, a property of the node (a group); a track of
        the object inside the group must be named ``<uuid of the object>.material.color``.
        """

        __slots__ = ()

        def lower(self) -> list[dict[str, Any]]:
            lowered: list[dict[str, Any]] = super().lower()
            for item in lowered:
                for track in item["clip"]["tracks"]:
                    if ".material." in track["name"]:
                        track["name"] = track["name"].lstrip(".")
                    compact_track(track)
            return lowered

    return _Animation


def _set_animation(commands: ModuleType) -> type:
    class _SetAnimation(commands.SetAnimation):  # type: ignore[name-defined]  # meshcat: no stubs, lazy import
        """meshcat's set_animation command, kept in the server's scene tree *after* the objects.

        A meshcat server (and :class:`~springbalance.viz.recorder.SceneRecorder`) stores a command at
        the tree node of its path and replays the tree depth first to every new browser and into the
        static page. meshcat's own command has the empty path, the root, so it replays *before* the
        objects, and tracks of an object that does not exist yet (the helix colour) fail to bind. This
        one is stored at a top-level node created after the scene. The browser ignores the path.
        """

        __slots__ = ()

        def lower(self) -> dict[str, Any]:
            data: dict[str, Any] = super().lower()
            data["path"] = f"/{ROOT}-animation"
            return data

    return _SetAnimation


#: msgpack extension code of a Float32Array in meshcat's viewer
FLOAT32_ARRAY = 0x17


def compact_track(track: dict[str, Any]) -> None:
    """Turn a lowered meshcat track's ``keys`` (a ``{time, value}`` map per key frame) into the
    ``times`` and flat ``values`` arrays that three.js's ``KeyframeTrack.parse`` also reads, each one
    float32 array (a msgpack Float32Array, which meshcat's viewer decodes): a third of the bytes.
    Float32 keeps 24 bits: 0.06 µm at 1 m. Tracks of booleans and strings are left as they are."""
    keys = track.get("keys")
    if not keys or track.get("type") not in ("vector3", "quaternion", "color", "number"):
        return
    times = np.asarray([key["time"] for key in keys], dtype=np.float32)
    values = np.asarray([key["value"] for key in keys], dtype=np.float32).ravel()
    del track["keys"]
    track["times"] = umsgpack.Ext(FLOAT32_ARRAY, times.tobytes())
    track["values"] = umsgpack.Ext(FLOAT32_ARRAY, values.tobytes())


def insert_before_body_end(page: str, fragment: str) -> str:
    """``page`` (HTML) with ``fragment`` inserted before its last ``</body>`` (appended when there is none)."""
    index = page.rfind("</body>")
    return page[:index] + fragment + page[index:] if index >= 0 else page + fragment
