"""The spring laws: one module per law, each registering its class in :data:`SPRING_TYPES`.

Every module of this folder is imported here (in this order, which is the registry's), so a new
law is one new module (a subclass of :class:`~springbalance.springs.laws.base.TwoPointSpring` or
:class:`~springbalance.springs.laws.base.Spring` with its own ``kind``), its name in the import line
below, and its tests: configs, saved designs, the config schema, the solver, reports, exports and scenes find
it through the registry. tests/springs/test_law_modules.py checks that no module of the folder is
left out.
"""

# ruff: noqa: I001  (the imports' order is the registry's order: the laws register themselves when imported)

from springbalance.springs.laws.base import SPRING_TYPES, Contribution, Spring, TwoPointSpring
from springbalance.springs.laws.compression import CompressionSpring
from springbalance.springs.laws.constant_force import ConstantForceSpring
from springbalance.springs.laws.extension import ExtensionSpring
from springbalance.springs.laws.gas import GasSpring
from springbalance.springs.laws.torsional import TorsionalSpring
from springbalance.springs.laws.zero_free_length import ZeroFreeLengthSpring

# the other laws register themselves when their module is imported (after the ones above: the registry's order)
from springbalance.springs.laws import coil, helical_compression, helical_extension, tabulated  # noqa: F401
from springbalance.springs.laws.directed import DirectedForce, DirectedGas

__all__ = [
    "SPRING_TYPES",
    "CompressionSpring",
    "ConstantForceSpring",
    "Contribution",
    "DirectedForce",
    "DirectedGas",
    "ExtensionSpring",
    "GasSpring",
    "Spring",
    "TorsionalSpring",
    "TwoPointSpring",
    "ZeroFreeLengthSpring",
]
