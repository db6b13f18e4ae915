"""The solve pipeline: :func:`solve` runs the steps of :mod:`springbalance.pipeline.steps` in order, from a
problem (or a config) to a :class:`~springbalance.results.result.DesignResult`."""

from springbalance.pipeline.run import solve
from springbalance.pipeline.state import SolveOptions, SolveState
from springbalance.pipeline.steps import STEPS

__all__ = ["STEPS", "SolveOptions", "SolveState", "solve"]
