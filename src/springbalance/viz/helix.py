r"""The helix of a drawn spring, in axial coordinates, and its placement between the two ends.

``x, y`` in metres, ``z`` the fraction ``s ∈ [0, 1]`` of the spring's length; at a pose the
spring's node gets the placement ``(R, x_a)`` with ``R e_z = u`` and the scale ``diag(1, 1, L)``
(see :mod:`springbalance.viz.tracks`).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import numpy.typing as npt


@dataclasses.dataclass(frozen=True)
class HelixStyle:
    """How a spring is drawn.

    Attributes:
        coils: number of active coils drawn.
        coil_radius: radius of the coil's centre line [m]; default 6 % of the spring's
            length in the first frame, kept within [6 mm, 40 mm].
        wire_radius: radius of the wire [m]; default a sixth of the coil radius, thinner
            when needed to leave a gap between neighbouring coils.
        lead: fraction of the length taken by the straight hook at each end.
        points_per_coil: centre-line points per coil.
        sides: facets around the wire.
    """

    coils: int = 10
    coil_radius: float | None = None
    wire_radius: float | None = None
    lead: float = 0.08
    points_per_coil: int = 24
    sides: int = 8

    def dimensions(self, reference_length: float) -> tuple[float, float]:
        """Coil and wire radius [m] of a spring ``reference_length`` [m] long."""
        coil = (
            self.coil_radius if self.coil_radius is not None else float(np.clip(0.06 * reference_length, 0.006, 0.04))
        )
        pitch = (1 - 2 * self.lead) * reference_length / max(self.coils, 1)  # [m] per coil
        wire = self.wire_radius if self.wire_radius is not None else min(coil / 6, pitch / 5)
        return coil, max(wire, 1e-4)


def helix_centerline(coils: int, coil_radius: float, lead: float = 0.08, points_per_coil: int = 24) -> np.ndarray:
    """Centre line of a helical spring in axial coordinates (M×3).

    ``x, y`` [m] across the axis, ``z`` the fraction of the length along it. The line starts
    at ``(0, 0, 0)``, runs straight (the hook) to the first coil at ``z = lead``, winds
    ``coils`` turns of radius ``coil_radius`` up to ``z = 1 - lead`` and runs straight back to
    the axis at ``(0, 0, 1)``.
    """
    if coils < 1 or coil_radius <= 0 or not 0 <= lead < 0.5:
        raise ValueError(
            f"helix needs coils ≥ 1, coil_radius > 0 and 0 ≤ lead < 0.5; got {coils}, {coil_radius}, {lead}"
        )
    t = np.linspace(0.0, 1.0, int(coils) * int(points_per_coil) + 1)
    angle = 2 * np.pi * coils * t
    coil = np.column_stack([coil_radius * np.cos(angle), coil_radius * np.sin(angle), lead + (1 - 2 * lead) * t])
    return np.vstack([[0.0, 0.0, 0.0], coil, [0.0, 0.0, 1.0]])


def helix_tube(
    centerline: np.ndarray, wire_radius: float, reference_length: float, sides: int = 8
) -> tuple[np.ndarray, np.ndarray]:
    """Triangle mesh of a wire of radius ``wire_radius`` [m] along ``centerline``.

    The tube is built in metres for a spring ``reference_length`` long (so the wire is
    round at that length) and returned in the axial coordinates of the centre line.
    Vertex 0 is the centre of the start cap, the last vertex the centre of the end cap:
    they are the centre line's ends, ``(0, 0, 0)`` and ``(0, 0, 1)``.

    Returns:
        vertices (numpy.ndarray): the tube's vertices (K×3).
        faces (numpy.ndarray): its triangles (F×3, indices into ``vertices``).
    """
    centerline = np.asarray(centerline, dtype=float)
    stretch = np.array([1.0, 1.0, reference_length])
    points = centerline * stretch  # [m]
    tangents = np.gradient(points, axis=0)
    tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)
    # parallel transport of a normal along the line (no twist of the tube)
    normal = np.cross(tangents[0], [1.0, 0.0, 0.0] if abs(tangents[0][0]) < 0.9 else [0.0, 1.0, 0.0])
    normal /= np.linalg.norm(normal)
    normals = np.empty_like(points)
    for i, tangent in enumerate(tangents):
        normal = normal - (normal @ tangent) * tangent
        normal /= np.linalg.norm(normal)
        normals[i] = normal
    binormals = np.cross(tangents, normals)
    angles = 2 * np.pi * np.arange(sides) / sides
    rings = points[:, None, :] + wire_radius * (
        np.cos(angles)[None, :, None] * normals[:, None, :] + np.sin(angles)[None, :, None] * binormals[:, None, :]
    )
    m = points.shape[0]
    vertices = np.vstack([centerline[:1], (rings / stretch).reshape(-1, 3), centerline[-1:]])
    faces = []
    ring = lambda i, k: 1 + i * sides + (k % sides)  # noqa: E731
    for i in range(m - 1):
        for k in range(sides):
            faces.append((ring(i, k), ring(i + 1, k), ring(i + 1, k + 1)))
            faces.append((ring(i, k), ring(i + 1, k + 1), ring(i, k + 1)))
    last = vertices.shape[0] - 1
    for k in range(sides):
        faces.append((0, ring(0, k + 1), ring(0, k)))
        faces.append((last, ring(m - 1, k), ring(m - 1, k + 1)))
    return vertices, np.array(faces, dtype=np.int64)


def spring_rotation(direction: npt.ArrayLike, side: npt.ArrayLike) -> np.ndarray:
    """Rotation ``R`` (3×3) with ``R e_z = direction`` and ``R e_x`` in the plane of ``side``.

    ``side`` is a fixed reference vector per spring, so the coils do not spin while the
    spring turns.
    """
    z = np.asarray(direction, dtype=float)
    norm = np.linalg.norm(z)
    z = z / norm if norm > 1e-12 else np.array([0.0, 0.0, 1.0])  # ends that meet: any axis will do
    x = np.asarray(side, dtype=float) - (np.asarray(side, dtype=float) @ z) * z
    if np.linalg.norm(x) < 1e-6:
        fallback = np.eye(3)[int(np.argmin(np.abs(z)))]
        x = fallback - (fallback @ z) * z
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def placement(rotation: npt.ArrayLike, translation: npt.ArrayLike) -> np.ndarray:
    """Homogeneous 4×4 matrix of a rotation and a translation."""
    matrix = np.eye(4)
    matrix[:3, :3] = rotation
    matrix[:3, 3] = translation
    return matrix
