"""What a design achieves: :class:`DesignResult`, the text and HTML reports, plots and a fixed design's payload study
(:func:`springbalance.payload_range`, which solves, is :mod:`springbalance.pipeline.payload`)."""

from springbalance.results.payload import PayloadRange, PayloadSweep, residual_vs_payload
from springbalance.results.result import DesignResult

__all__ = ["DesignResult", "PayloadRange", "PayloadSweep", "residual_vs_payload"]
