r"""How deep a spring's centre line runs inside one of its own anchor bodies, beyond its anchor.

A spring anchored at ``p`` on body ``B`` always touches ``B`` near ``p``; what it must not do is run on
*inside* ``B``. At a pose, with the spring's centre line from its own end ``p`` to its other end ``o``
(world, [m]), unit axis ``u`` and length ``ℓ``:

- the anchor's way out of ``B`` is its depth ``d_p = max(0, -s_B(p))`` (``s_B``: signed distance to ``B``'s
  collision objects, meshes as their convex hulls); the other end's own depth in ``B`` is ``d_o``;
- the stretches ``d_p + r +`` :data:`OWN_STRETCH` from ``p`` and ``d_o + r +`` :data:`OWN_STRETCH` from ``o``
  (``r``: the spring's capsule radius) are exempt: a spring that leaves ``B`` straight out has left it there;
- the rest of the centre line, ``p + t u`` for ``t`` between the two stretches, must not enter ``B``: its
  signed distance to ``B`` (coal's, for a segment of radius :data:`LINE`) is ``-depth`` where it does.

:func:`centre_line_inside` gives that depth [m] and the closest approach (the deepest point of the centre
line and the point of ``B``'s surface nearest it); :mod:`springbalance.results.own_link` turns it into the
``inside_own_link`` warning and :mod:`springbalance.viz.own_link_marks` into the scene's marker.
"""

from __future__ import annotations

import numpy as np

from springbalance.model.collision import CollisionScene, Contact

#: the stretch [m] beyond the anchor's way out of its link and the coil's radius that counts as the anchor's
OWN_STRETCH = 0.003
#: depths [m] below this are the round-off of the distance computation
DEPTH_TOLERANCE = 1e-4
#: the segment radius [m] of the centre line (coal measures a capsule)
LINE = 1e-9


def centre_line_inside(
    scene: CollisionScene, own: np.ndarray, other: np.ndarray, objects: list[int], own_inside: float, radius: float
) -> tuple[float, Contact | None]:
    """How deep [m] the centre line from ``own`` to ``other`` (world, [m], at the pose ``scene`` is placed at),
    less the stretches at both ends (see the module documentation; ``own_inside``: the own anchor's depth in its
    body [m], ``radius``: the capsule radius [m]), lies inside the collision objects ``objects`` of the scene
    (its body's), and the contact with the deepest of them (None when the stretches leave no segment).
    The depth is 0 where the line does not enter them."""
    length = float(np.linalg.norm(other - own))
    if length <= 0:
        return 0.0, None
    axis = (other - own) / length
    # the other anchor's depth in this body: its own way out, exempt like this end's
    other_inside = max(0.0, -min(scene.capsule_distance(other, other, LINE, i).distance for i in objects))
    start = own_inside + radius + OWN_STRETCH
    stop = length - (other_inside + radius + OWN_STRETCH)
    if stop <= start:
        return 0.0, None
    contact = min(
        (scene.capsule_distance(own + start * axis, own + stop * axis, LINE, i) for i in objects),
        key=lambda found: found.distance,
    )
    return max(0.0, -contact.distance), contact
