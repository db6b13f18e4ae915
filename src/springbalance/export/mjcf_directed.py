"""A force along a fixed direction in the MuJoCo export (docs/model.md §3.11): a site actuator with a reference site.

A :class:`~springbalance.springs.laws.directed.DirectedSpring` becomes a site ``<spring>_anchor_a``
at its anchor, a site ``<spring>_guide`` at the origin of its guide's frame, and a ``general``
actuator with ``site`` and ``refsite``: MuJoCo's length is then ``gear · (p − o)`` in the reference
site's frame, ``s = u · (p − o)`` with ``gear = (u, 0, 0, 0)``, and the actuator force ``f``
enters the joints as ``(∂s/∂q)ᵀ f``, the moment of the reaction on a moving guide included. The
force ``f = f0 + f1 s`` of the laws is affine in the stroke, so the actuator's affine bias
``biasprm = (f0, f1, 0)`` with ``gainprm = 0`` is the law exactly, whatever the control.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

from springbalance.export.common import anchor_link_name, spring_name, vector
from springbalance.springs.laws.directed import DirectedSpring

if TYPE_CHECKING:  # lxml (no stubs) is imported when a model is exported
    from lxml.etree import _Element


def add_directed(body: Callable[[str], _Element], actuator: _Element, spring: DirectedSpring, record: dict) -> None:
    """Add the sites of ``spring`` to the bodies (``body(name)`` → its MJCF element) and its actuator to
    ``actuator``; ``record``: the spring's values (:attr:`EvaluatedDesign.springs`)."""
    from lxml import etree

    name = spring_name(spring)
    site = anchor_link_name(name, "a")
    etree.SubElement(body(record["a"]["body"]), "site", name=site, pos=vector(record["a"]["point"]), size="0.01")
    reference = f"{name}_guide"
    etree.SubElement(body(spring.guide), "site", name=reference, pos="0 0 0", size="0.005")
    constant, slope = spring.actuator_bias(record)  # f = f0 + f1 s [N], [N/m]
    etree.SubElement(
        actuator,
        "general",
        name=f"{name}_directed_force",
        site=site,
        refsite=reference,
        gear=vector([*spring.direction, 0.0, 0.0, 0.0]),
        gainprm="0",
        biastype="affine",
        biasprm=vector([constant, slope, 0.0]),
    )
