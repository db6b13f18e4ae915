"""The deprecated methods of a design problem (removed in springbalance 0.3): each warns once and calls its new home.

:class:`DeprecatedProblemMethods` is a base of :class:`~springbalance.design.problem.DesignProblem`; the new homes
are ``springbalance.solve(problem, ...)`` and :class:`~springbalance.results.result.DesignResult`. Their imports
point up the layers (the shims' only upward imports, listed in pyproject.toml's import contracts).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from springbalance.deprecation import warn_deprecated


class DeprecatedProblemMethods:
    """``solve``, ``result`` and ``scenario_results`` of a design problem, deprecated."""

    def solve(
        self,
        starts: int = 8,
        seed: int = 0,
        method: str = "auto",
        progress: bool | None = None,
        max_iterations: int = 100,
        tolerance: float = 1e-8,
        polish_iterations: int | None = None,
        standard_wire: bool = True,
        workers: int | None = None,
    ) -> Any:
        """Deprecated: ``springbalance.solve(problem, ...)`` (same options, same design)."""
        from springbalance.pipeline.run import solve  # deprecated shim: the one upward import, listed in pyproject

        warn_deprecated("DesignProblem.solve(...)", "springbalance.solve(problem, ...)")
        return solve(
            self,  # type: ignore[arg-type]  # a DesignProblem, whose base this is
            starts=starts,
            seed=seed,
            method=method,
            progress=progress,
            max_iterations=max_iterations,
            tolerance=tolerance,
            polish_iterations=polish_iterations,
            standard_wire=standard_wire,
            workers=workers,
        )

    def result(self, x: np.ndarray, **info: Any) -> Any:
        """Deprecated: ``springbalance.DesignResult(problem, x, **info)`` (no optimisation)."""
        from springbalance.results.result import DesignResult  # deprecated shim, listed in pyproject

        warn_deprecated("DesignProblem.result(x)", "springbalance.DesignResult(problem, x)")
        return DesignResult(self, np.asarray(x, dtype=float), **info)  # type: ignore[arg-type]  # a DesignProblem

    def scenario_results(self, x: np.ndarray) -> list:
        """Deprecated: ``DesignResult(problem, x).scenario_results()``."""
        from springbalance.results.result import DesignResult  # deprecated shim, listed in pyproject

        warn_deprecated("DesignProblem.scenario_results(x)", "DesignResult(problem, x).scenario_results()")
        return DesignResult(self, np.asarray(x, dtype=float)).scenario_results()  # type: ignore[arg-type]
