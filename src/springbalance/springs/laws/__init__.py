"""The spring laws: one module per law, each registering its class in :data:`SPRING_TYPES`.

Every module of this folder is imported here, so a new law is one new module (a subclass of
:class:`~springbalance.springs.laws.base.TwoPointSpring` or
:class:`~springbalance.springs.laws.base.Spring` with its own ``kind``) plus its tests:
configs, saved designs, the config schema, the solver, reports, exports and scenes find it
through the registry.
"""

import importlib
import pkgutil

from springbalance.springs.laws.base import SPRING_TYPES, Contribution, Spring, TwoPointSpring
from springbalance.springs.laws.compression import CompressionSpring
from springbalance.springs.laws.constant_force import ConstantForceSpring
from springbalance.springs.laws.extension import ExtensionSpring
from springbalance.springs.laws.gas import GasSpring
from springbalance.springs.laws.torsional import TorsionalSpring
from springbalance.springs.laws.zero_free_length import ZeroFreeLengthSpring

for _module in pkgutil.iter_modules(__path__):
    importlib.import_module(f"{__name__}.{_module.name}")

__all__ = ["SPRING_TYPES", "CompressionSpring", "ConstantForceSpring", "Contribution", "ExtensionSpring", "GasSpring",
           "Spring", "TorsionalSpring", "TwoPointSpring", "ZeroFreeLengthSpring"]
