"""The base classes of every spring law and the registry of laws: this module gathers them from
:mod:`springbalance.springs.laws.spring` (:class:`Spring`, :class:`Contribution`, :data:`SPRING_TYPES`)
and :mod:`springbalance.springs.laws.two_point` (:class:`TwoPointSpring`, :class:`HelicalSpringMixin`),
where they are defined.
"""

from __future__ import annotations

from springbalance.springs.laws.spring import (
    SPRING_TYPES,
    Contribution,
    PositiveNumber,
    Spring,
    StretchRatio,
    _checked_parameter,
    _positive_option,
)
from springbalance.springs.laws.two_point import HelicalSpringMixin, TwoPointSpring

__all__ = [
    "SPRING_TYPES",
    "Contribution",
    "HelicalSpringMixin",
    "PositiveNumber",
    "Spring",
    "StretchRatio",
    "TwoPointSpring",
    "_checked_parameter",
    "_positive_option",
]
