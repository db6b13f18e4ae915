"""The spring elements: anchors and parameters, the laws (one module each), routing over pulleys, spring mass,
sizing, constraints.

A spring law is one module of :mod:`springbalance.springs.laws`; it registers itself in
:data:`SPRING_TYPES`, through which records (:func:`spring_from_dict`), the config schema, the
solver, the exports and the scenes find it.
"""

from springbalance.springs.laws import (
    SPRING_TYPES,
    CompressionSpring,
    ConstantForceSpring,
    Contribution,
    ExtensionSpring,
    GasSpring,
    Spring,
    TorsionalSpring,
    TwoPointSpring,
    ZeroFreeLengthSpring,
)
from springbalance.springs.laws.helical_compression import HelicalCompressionSpring
from springbalance.springs.laws.helical_extension import HelicalExtensionSpring
from springbalance.springs.mass import CoilMass, FixedMass
from springbalance.springs.params import Anchor, Free, Plane, Pulley, Segment
from springbalance.springs.records import spring_from_dict

__all__ = [
    "SPRING_TYPES",
    "Anchor",
    "CoilMass",
    "CompressionSpring",
    "ConstantForceSpring",
    "Contribution",
    "ExtensionSpring",
    "FixedMass",
    "Free",
    "GasSpring",
    "HelicalCompressionSpring",
    "HelicalExtensionSpring",
    "Plane",
    "Pulley",
    "Segment",
    "Spring",
    "TorsionalSpring",
    "TwoPointSpring",
    "ZeroFreeLengthSpring",
    "spring_from_dict",
]
