"""The spring elements: anchors and parameters, one module per law, spring mass, sizing, constraints."""

from springbalance.springs.laws import (SPRING_TYPES, CoilMass, CompressionSpring, ConstantForceSpring,
                                        ExtensionSpring, GasSpring, Spring, TorsionalSpring, TwoPointSpring,
                                        ZeroFreeLengthSpring, spring_from_dict)
from springbalance.springs.params import Anchor, Free, Plane, Segment

__all__ = ["SPRING_TYPES", "Anchor", "CoilMass", "CompressionSpring", "ConstantForceSpring", "ExtensionSpring",
           "Free", "GasSpring", "Plane", "Segment", "Spring", "TorsionalSpring", "TwoPointSpring",
           "ZeroFreeLengthSpring", "spring_from_dict"]
