"""The two-spring design whose tolerance box the tolerance tests enumerate by brute force (all 8² = 64 builds):
two ideal extension springs on urdf/two_link_planar.urdf, and the box they are built within."""

from __future__ import annotations

import itertools

import springbalance as sb
from springbalance.design.tolerance_spec import ToleranceSpec

#: ± 10 % rate, ± 3 N initial tension, ± 4 mm free length
SPEC = ToleranceSpec.from_record({"rate": 0.1, "initial_tension": 3.0, "free_length": 0.004})
#: (k [N/m], l0 [m], F0 [N]) of the shoulder spring and of the forearm spring
LAWS = [(900.0, 0.12, 10.0), (300.0, 0.15, 4.0)]


def two_springs(laws) -> list:
    """The shoulder (ground → link1) and forearm (link1 → link2) springs with the laws ``laws``."""
    (k1, l1, f1), (k2, l2, f2) = laws
    return [
        sb.ExtensionSpring(
            sb.Anchor("universe", (0.0, 0.0, 0.25)), sb.Anchor("link1", (0.3, 0.0, 0.0)), "shoulder",
            stiffness=k1, free_length=l1, initial_tension=f1, keep_tension=False,
        ),
        sb.ExtensionSpring(
            sb.Anchor("link1", (0.2, 0.0, 0.05)), sb.Anchor("link2", (0.25, 0.0, 0.0)), "forearm",
            stiffness=k2, free_length=l2, initial_tension=f2, keep_tension=False,
        ),
    ]  # fmt: skip


def corner_laws():
    """Every build's corner ``(c1, c2)`` (each ``(a, b, c)`` in {−1, 1}³ for rate, tension, length) and laws."""
    for c1, c2 in itertools.product(itertools.product((-1, 1), repeat=3), repeat=2):
        yield (
            (c1, c2),
            [(k * (1 + a * 0.1), l0 + c * 0.004, f0 + b * 3.0) for (k, l0, f0), (a, b, c) in zip(LAWS, (c1, c2))],
        )
