"""springbalance.springs.sizing still gives every name it defined before its split, as the same objects."""

from __future__ import annotations

from springbalance.springs import helical_formulas, helical_option, materials, sizing
from springbalance.springs.laws import base, spring, two_point


def test_sizing_re_exports_the_helical_modules():
    for module in (helical_formulas, materials, helical_option):
        for name in sizing.__all__:
            if hasattr(module, name) and not name.startswith("_"):
                assert getattr(sizing, name) is getattr(module, name), name
    assert sizing.size_helical_spring.__module__ == "springbalance.springs.sizing"


def test_laws_base_re_exports_the_spring_and_two_point_modules():
    assert base.Spring is spring.Spring and base.SPRING_TYPES is spring.SPRING_TYPES
    assert base.TwoPointSpring is two_point.TwoPointSpring and base.HelicalSpringMixin is two_point.HelicalSpringMixin
