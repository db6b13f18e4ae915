"""The ``solve`` section of a config: the options of the multi-start solve (:class:`SolveRecord`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Union

import annotated_types
from pydantic import ConfigDict

from springbalance.design.standard_wire import checked_wire_sizes
from springbalance.errors import InputError
from springbalance.io.schema.fields import (
    Counting,
    Method,
    NonNegativeCount,
    Positive,
    Record,
    Seed,
    Text,
    VerifyMode,
    abbreviated,
    at_most_one,
    by_shape,
    fail,
    optional,
)

if TYPE_CHECKING:  # what by_shape builds at run time (a tagged union), as mypy can read it
    _StockSpec = Union[str, list[str]]
else:
    _StockSpec = by_shape(list=Annotated[list[Text], annotated_types.MinLen(1)], scalar=Text)


class SolveRecord(Record, title="Solve"):
    """Options of the multi-start solve (the command line's --starts, --seed, --seeds, --method, --workers override
    them)."""

    model_config = ConfigDict(json_schema_extra=at_most_one(("seed", "seeds")))

    @classmethod
    def _check_record(cls, data: dict) -> None:
        if "seed" in data and "seeds" in data:
            raise fail("seed_and_seeds", "give seed (one) or seeds (solve at each, keep the best), not both")
        seeds = data.get("seeds")
        if isinstance(seeds, list) and len(set(map(repr, seeds))) != len(seeds):
            raise fail("repeated_seed", f"seeds must be distinct, got {abbreviated(seeds)}", "seeds")
        sizes = data.get("wire_sizes")  # numbers > 0 here; the fields' own checks say what else is wrong
        if isinstance(sizes, list) and sizes and all(type(size) in (int, float) and size > 0 for size in sizes):
            try:
                checked_wire_sizes(sizes)
            except InputError as error:
                raise fail("wire_sizes", str(error).removeprefix("wire_sizes: "), "wire_sizes") from None

    starts: Counting = optional(
        "starts of the multi-start: the initial guess, then scrambled Sobol points of the bounds", shown=8
    )
    seed: Seed = optional("seed of the start points; results are deterministic given it", shown=0)
    seeds: Annotated[list[Seed], annotated_types.MinLen(1)] = optional(
        "solve at each of these seeds instead of one, and keep the best design: the first that passes every "
        "check, by objective (docs/guides/clearance.md); the report lists what each seed gave"
    )
    method: Method = optional(
        "least_squares (bounded Gauss-Newton, for rms and pe_variance), ipopt (general NLP) or auto", shown="auto"
    )
    max_iterations: Counting = optional("iteration budget of each start (and of each IPOPT phase)", shown=100)
    tolerance: Positive = optional(
        "least squares stop when a step lowers the cost by less than this "
        "fraction [1]; IPOPT uses min(tolerance, 1e-8)",
        shown=1e-8,
    )
    polish_iterations: NonNegativeCount = optional(
        "further iterations for the best starts when they stopped on the iteration limit (0: none); default 4x "
        "max_iterations, and with free helical coils 16x without a fit to the arm and 2x with one"
    )
    standard_wire: bool = optional(
        "after the solve, round every coil's free wire diameter to a standard size (wire_sizes) and re-optimise "
        "the rest (docs/model.md §3.8)",
        shown=True,
    )
    wire_sizes: Annotated[list[Positive], annotated_types.MinLen(1)] = optional(
        "the wire diameters [m] your spring maker draws (for example [0.0030, 0.0032, 0.0034]): the sizes the wires "
        "are rounded to and that the report judges each coil's wire against; default the preferred metric series "
        "(docs/guides/coils-and-stock.md)"
    )
    workers: Counting = optional(
        "processes that run the starts at once (the design does not depend on it); "
        "default $SPRINGBALANCE_WORKERS, else the number of cores, once a start "
        "lasts long enough to pay for the pool"
    )
    verify: VerifyMode = optional(
        "the check of the design at 10x as many unseen poses (docs/model.md §12): resolve (re-solve with the "
        "worst poses added where a rule fails there), report (only report) or off",
        shown="resolve",
    )
    stock: _StockSpec = optional(
        "then replace each extension and compression spring by a stock part and re-optimise the anchors: "
        "ms24585 (compression), ms24586 (extension), the standard catalogues, or a CSV catalogue (relative "
        "to the config file); a list, or one string separated by commas (the command line's --stock "
        "overrides it; docs/guides/coils-and-stock.md)"
    )
