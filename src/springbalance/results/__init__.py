"""What a design achieves: :class:`DesignResult`, the text and HTML reports, plots and payload studies."""

from springbalance.results.payload import PayloadRange, PayloadSweep, payload_range, residual_vs_payload
from springbalance.results.result import DesignResult

__all__ = ["DesignResult", "PayloadRange", "PayloadSweep", "payload_range", "residual_vs_payload"]
