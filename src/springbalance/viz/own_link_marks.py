"""Where a spring runs inside its own anchor link in each frame of a scene: the depth and the point its marker
goes to (:attr:`~springbalance.viz.tracks.SpringTrack.inside`, :attr:`~springbalance.viz.tracks.SpringTrack.inside_point`).

The report flags a spring whose centre line runs on inside its own anchor link beyond its anchor (the
``inside_own_link`` warning of :mod:`springbalance.results.own_link`, over the design's workspace); the scene
draws it red and, in every frame of its path where the same rule finds it inside
(:func:`~springbalance.model.inside_link.centre_line_inside`, the deeper of its two ends), puts a marker halfway
between the deepest point of its centre line and the link's surface nearest it. Meshes count as their convex
hulls; an arm without collision geometry, and a routed spring, get no marker. Lengths in m.
"""

from __future__ import annotations

from collections.abc import Collection

import numpy as np

from springbalance.errors import InputError
from springbalance.model.collision import CollisionScene, capsule_radius, collision_geometry
from springbalance.model.inside_link import DEPTH_TOLERANCE, centre_line_inside
from springbalance.model.mechanism import Mechanism
from springbalance.model.surfaces import surface_distance
from springbalance.viz.tracks import SpringTrack


def add_own_link(
    tracks: list[SpringTrack],
    records: dict[str, dict],
    mechanism: Mechanism,
    configurations: np.ndarray,
    names: Collection[str],
) -> None:
    """Set :attr:`SpringTrack.inside` and :attr:`SpringTrack.inside_point` of the tracks named in ``names``
    over ``configurations`` (N×nq), and their capsule :attr:`SpringTrack.radius` [m] when none is set (the
    record's, :func:`~springbalance.model.collision.capsule_radius`). Nothing is set without collision geometry."""
    chosen = [track for track in tracks if track.name in names and track.cable is None]
    if not chosen:
        return
    try:
        geometry = collision_geometry(mechanism)
    except InputError:  # no URDF, or no <collision> elements: nothing to measure
        return
    scene = CollisionScene(mechanism, geometry, convex=True)
    ends = []  # (track, own positions N×3, other positions N×3, the body's objects, the anchor's depth, radius)
    for track in chosen:
        radius = capsule_radius(records[track.name])
        track.radius = radius if track.radius is None else track.radius
        track.inside = np.zeros(len(configurations))
        track.inside_point = np.full((len(configurations), 3), np.nan)
        for own, (body, point) in enumerate(zip(track.bodies, track.points)):
            objects = [i for i, link in enumerate(scene.bodies) if link == body]
            if objects:
                depth = max(0.0, -surface_distance(mechanism, geometry, body, point)[0])
                positions = (track.starts, track.ends) if own == 0 else (track.ends, track.starts)
                ends.append((track, *positions, objects, depth, radius))
    for frame, q in enumerate(configurations):
        scene.place(q)
        for track, own_at, other_at, objects, own_inside, radius in ends:
            depth, contact = centre_line_inside(scene, own_at[frame], other_at[frame], objects, own_inside, radius)
            if contact is not None and depth > DEPTH_TOLERANCE and depth > track.inside[frame]:  # type: ignore[index]
                track.inside[frame] = depth  # type: ignore[index]
                track.inside_point[frame] = (contact.on_capsule + contact.on_object) / 2  # type: ignore[index]
