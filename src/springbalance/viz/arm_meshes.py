"""The arm's mesh files, made small for the scene page: decimated once per file, one part per colour.

A URDF's visual meshes (COLLADA, STL, OBJ) are often finer than a scene needs: the UR5's seven
files of example-robot-data hold 95 000 triangles, 8.9 MB once inlined into a page. Each file is
read with trimesh (its node transforms applied, so the vertices are in the geometry's frame, the
same as Pinocchio's), its pieces grouped by colour (a COLLADA file's materials, unless the URDF
overrides the material), each group's coincident vertices merged, and the group decimated by
quadric edge collapse (:func:`fast_simplification.simplify`, Garland and Heckbert's error metric)
down to :data:`KEEP` of its triangles, never below :data:`MIN_TRIANGLES`. Quadric collapse keeps
the silhouette and the flat faces of machined parts; what goes are the fine tessellations of
fillets and screw heads that no one sees at the scene's scale. Lengths in m.

Each part is sent once as a ``TriangularMeshGeometry`` (float32 vertices, uint32 faces) below the
geometry's node; the animation moves the node, so the parts are shared by every frame.
"""

from __future__ import annotations

import dataclasses
import functools
import warnings
from pathlib import Path
from typing import Any

import numpy as np

#: Fraction of each mesh part's triangles that the decimation keeps.
KEEP = 0.2
#: A part with fewer triangles than this is kept as it is.
MIN_TRIANGLES = 400
#: Mesh files that are drawn through this module (others go to Pinocchio's own loader).
MESH_SUFFIXES = (".dae", ".stl", ".obj")


@dataclasses.dataclass(frozen=True)
class MeshPart:
    """One colour of a mesh file: ``vertices`` (V×3, float32) [m] in the geometry's frame, ``faces``
    (F×3, uint32) and ``color`` (RGB in [0, 1]), or None for the URDF's colour."""

    vertices: np.ndarray
    faces: np.ndarray
    color: tuple[float, float, float] | None


def decimate(vertices: np.ndarray, faces: np.ndarray, keep: float = KEEP) -> tuple[np.ndarray, np.ndarray]:
    """The mesh (``vertices`` V×3 [m], ``faces`` F×3) decimated by quadric edge collapse to about
    ``keep`` of its triangles (at least :data:`MIN_TRIANGLES`; smaller meshes come back as they are)."""
    import fast_simplification

    faces = np.asarray(faces, dtype=np.int64)
    if len(faces) <= MIN_TRIANGLES:
        return np.asarray(vertices, dtype=np.float64), faces
    reduction = 1.0 - max(keep, MIN_TRIANGLES / len(faces))
    points, triangles = fast_simplification.simplify(
        np.asarray(vertices, dtype=np.float64), faces, target_reduction=reduction
    )
    return np.asarray(points, dtype=np.float64), np.asarray(triangles, dtype=np.int64)


def _color(mesh: Any) -> tuple[float, float, float] | None:
    """The diffuse colour (RGB in [0, 1]) of a trimesh mesh's material or colour visuals, else None."""
    visual = getattr(mesh, "visual", None)
    material = getattr(visual, "material", None)
    rgba = getattr(material, "main_color", None) if material is not None else getattr(visual, "main_color", None)
    if rgba is None:
        return None
    red, green, blue = (float(c) / 255.0 for c in np.asarray(rgba)[:3])
    return red, green, blue


@functools.lru_cache(maxsize=32)
def mesh_parts(path: str, file_colors: bool = True, keep: float = KEEP) -> tuple[MeshPart, ...]:
    """The parts of the mesh file ``path``, one per colour (a single part without colour when
    ``file_colors`` is False), decimated (:func:`decimate`). Read once per file and ``keep``."""
    import trimesh

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # trimesh and pycollada warn about unused COLLADA elements
        scene: Any = trimesh.load(path, force="scene")
    groups: dict[tuple[float, float, float] | None, list[Any]] = {}
    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        mesh = scene.geometry[name]
        if not hasattr(mesh, "faces") or len(mesh.faces) == 0:
            continue
        mesh = mesh.copy()
        mesh.apply_transform(transform)
        groups.setdefault(_color(mesh) if file_colors else None, []).append(mesh)
    parts = []
    for color, meshes in groups.items():
        merged: Any = trimesh.util.concatenate([trimesh.Trimesh(m.vertices, m.faces, process=False) for m in meshes])
        merged.merge_vertices()
        vertices, faces = decimate(merged.vertices, merged.faces, keep)
        parts.append(MeshPart(np.asarray(vertices, dtype=np.float32), np.asarray(faces, dtype=np.uint32), color))
    return tuple(parts)


def drawable(geometry_object: Any) -> bool:
    """True when the geometry is a mesh file this module draws (COLLADA, STL or OBJ)."""
    path = str(getattr(geometry_object, "meshPath", "") or "")
    return Path(path).suffix.lower() in MESH_SUFFIXES and Path(path).is_file()


def hex_color(rgb: tuple[float, float, float] | np.ndarray) -> int:
    """RGB in [0, 1] as the 0xRRGGBB integer of meshcat materials."""
    red, green, blue = (int(round(255 * float(c))) for c in list(rgb)[:3])
    return (red << 16) | (green << 8) | blue


def draw_mesh_file(node: Any, geometry_object: Any, mg: Any) -> None:
    """Draw the mesh file of ``geometry_object`` (a Pinocchio ``GeometryObject``) below the meshcat
    ``node`` as its decimated parts (:func:`mesh_parts`), ``part0``, ``part1`` …: COLLADA colours unless
    the URDF overrides the material, else the URDF's colour (``meshColor``)."""
    suffix = Path(geometry_object.meshPath).suffix.lower()
    file_colors = suffix == ".dae" and not geometry_object.overrideMaterial
    rgba = np.asarray(geometry_object.meshColor, dtype=float)
    for index, part in enumerate(mesh_parts(str(geometry_object.meshPath), file_colors)):
        color = part.color if part.color is not None else tuple(rgba[:3])
        material = mg.MeshPhongMaterial(color=hex_color(color), shininess=30)
        if rgba[3] < 1.0:
            material.transparent, material.opacity = True, float(rgba[3])
        node[f"part{index}"].set_object(mg.TriangularMeshGeometry(part.vertices, part.faces), material)
