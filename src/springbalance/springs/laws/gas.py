r"""Gas spring (docs/model.md §3.4): the compression law, no coil to size."""

from __future__ import annotations

from typing import Any

from springbalance.errors import InputError
from springbalance.springs.laws.compression import CompressionSpring
from springbalance.springs.laws.spring import PositiveNumber
from springbalance.springs.laws.two_point import TwoPointSpring
from springbalance.springs.params import Anchor


class GasSpring(CompressionSpring):
    r"""Gas spring: the law of :class:`CompressionSpring`, preload ``F0`` at the extended length ``l0``,

    .. math:: F = -\bigl(F_0 + k (l_0 - L)\bigr),\qquad V_s = F_0 (l_0 - L) + k (l_0 - L)^2 / 2,

    where ``k`` [N/m] is the progression of the gas force over the stroke. It always stays
    compressed (``L ≤ l0``, option ``stays_compressed``); ``stroke`` [m] limits the compression
    (``L ≥ l0 - stroke``). No ``helical`` option.
    """

    kind = "gas"
    ideal = None
    required_options = ()
    option_types = {**TwoPointSpring.option_types, "stays_compressed": bool, "stroke": PositiveNumber | None}
    helical_kind = None  # not a coil: nothing to size

    def __init__(self, a: Anchor, b: Anchor, name: str | None = None, **kwargs: Any):
        if kwargs.get("helical") is not None:
            raise InputError(f"GasSpring {name or ''}: a gas spring has no helical option")
        super().__init__(a, b, name, **kwargs)
