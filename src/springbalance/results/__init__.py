"""What a design achieves: :class:`DesignResult`, the text and HTML reports, plots and a fixed design's payload study
(:func:`springbalance.payload_range`, which solves, is :mod:`springbalance.pipeline.payload`), and what each seed gave
when a design was solved at several (:class:`SeedSearch`)."""

from springbalance.results.payload import PayloadRange, PayloadSweep, residual_vs_payload
from springbalance.results.result import DesignResult
from springbalance.results.seed_search import SeedRun, SeedSearch

__all__ = ["DesignResult", "PayloadRange", "PayloadSweep", "SeedRun", "SeedSearch", "residual_vs_payload"]
