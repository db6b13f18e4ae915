"""The spring-law package imports every module of its folder, so each law is in the registry."""

from __future__ import annotations

import pkgutil
import sys

import springbalance.springs.laws as laws


def test_every_module_of_the_laws_folder_is_imported_by_the_package():
    modules = {info.name for info in pkgutil.iter_modules(laws.__path__)}
    assert modules >= {"base", "coil", "tabulated", "zero_free_length"}
    missing = [name for name in sorted(modules) if f"{laws.__name__}.{name}" not in sys.modules]
    assert missing == []


def test_each_law_with_a_kind_is_registered_under_it():
    from springbalance.springs.laws.helical_extension import HelicalExtensionSpring
    from springbalance.springs.laws.tabulated import TabulatedSpring

    assert laws.SPRING_TYPES["tabulated"] is TabulatedSpring
    assert laws.SPRING_TYPES["extension"] is HelicalExtensionSpring
    assert laws.SPRING_TYPES["extension:ideal"] is laws.ExtensionSpring
