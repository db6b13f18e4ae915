"""The red markers of a scene: a translucent red sphere at the closest point of a spring that is drawn red.

- Below the clearance margin (:meth:`~springbalance.viz.tracks.SpringTrack.below_margin`): halfway between
  the spring's capsule and the nearest collision object (:attr:`~springbalance.viz.tracks.SpringTrack.closest`),
  radius ``r + m`` (``r``: the capsule radius [m], ``m`` = :data:`MARKER_RADIUS`).
- Inside its own anchor link (:attr:`~springbalance.viz.tracks.SpringTrack.inside`, depth ``d`` [m]): halfway
  between the deepest point of its centre line and the link's surface nearest it
  (:attr:`~springbalance.viz.tracks.SpringTrack.inside_point`), radius ``r + m + d / 2``, so that the sphere
  reaches ``r + m`` out of the link, where it can be seen.
- Elsewhere the marker shrinks to nothing (scale 1e-6) at the spring's middle.

The sphere is drawn once at radius ``r + m`` and scaled per frame by the animation. Lengths in m.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from springbalance.viz.colors import CLEARANCE_COLOR
from springbalance.viz.helix import placement
from springbalance.viz.tracks import SpringTrack

#: Radius [m] of the marker beyond the spring's capsule radius.
MARKER_RADIUS = 0.012
#: Opacity of the marker's red.
MARKER_OPACITY = 0.55


def has_marker(spring: SpringTrack) -> bool:
    """True when ``spring`` gets a marker in some frame: below the clearance margin, or inside its own link."""
    below = spring.closest is not None and spring.below_margin is not None and bool(np.any(spring.below_margin))
    inside = spring.inside is not None and bool(np.any(spring.inside > 0))
    return below or inside


def marker_size(spring: SpringTrack) -> float:
    """The radius [m] the marker is drawn at: the capsule radius (else the coil's) plus :data:`MARKER_RADIUS`."""
    return (spring.radius or spring.coil_radius) + MARKER_RADIUS


def marker_placement(spring: SpringTrack, frame: int) -> tuple[np.ndarray, float]:
    """Where the marker of ``spring`` is at ``frame`` [m] (world) and its scale (see the module documentation)."""
    below = spring.below_margin is not None and bool(spring.below_margin[frame])
    closest = spring.closest[frame] if spring.closest is not None else np.full(3, np.nan)
    if below and np.all(np.isfinite(closest)):
        return closest, 1.0
    if spring.inside is not None and spring.inside_point is not None and spring.inside[frame] > 0:
        size = marker_size(spring)
        return spring.inside_point[frame], (size + spring.inside[frame] / 2) / size
    return (spring.starts[frame] + spring.ends[frame]) / 2, 1e-6


def draw_marker(root: Any, spring: SpringTrack, geometry: Any) -> None:
    """Draw the marker of ``spring`` at its first frame below ``root`` (``geometry``: ``meshcat.geometry``)."""
    if not has_marker(spring):
        return
    marker = root["markers"][spring.name]
    marker.set_object(
        geometry.Sphere(marker_size(spring)),
        geometry.MeshPhongMaterial(color=CLEARANCE_COLOR, opacity=MARKER_OPACITY),
    )
    point, scale = marker_placement(spring, 0)
    marker.set_transform(placement(scale * np.eye(3), point))


def animate_marker(root: Any, spring: SpringTrack, frame: int) -> None:
    """Key frame ``frame`` of the marker of ``spring`` below ``root`` (a frame of the animation)."""
    if not has_marker(spring):
        return
    point, scale = marker_placement(spring, frame)
    root["markers"][spring.name].set_property("position", "vector3", [float(v) for v in point])
    root["markers"][spring.name].set_property("scale", "vector3", [float(scale)] * 3)
