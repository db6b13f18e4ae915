"""Typed failures.

Every error a user can cause is a :class:`SpringBalanceError` whose message names the
culprit (file, body, joint, config key or value). The command-line tool prints the
message on one line and exits with status 2.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Iterable

if TYPE_CHECKING:
    import numpy as np


class SpringBalanceError(Exception):
    """Base class of every error springbalance raises on purpose."""


class InputError(SpringBalanceError, ValueError):
    """Bad input: unknown names, inconsistent bounds, malformed files or configs."""


class ConfigError(InputError):
    """A configuration file (YAML/JSON) that does not match the documented schema."""


class SolverError(SpringBalanceError):
    """No start of a design problem produced a usable design.

    Attributes:
        problem: the :class:`~springbalance.design.problem.DesignProblem` that was solved.
        starts: per-start records with the solver's own status string.
    """

    # problem and starts are a DesignProblem and its StartRecords: this bottom layer may not import
    # springbalance.design (not even under TYPE_CHECKING), so they are typed Any here.
    def __init__(self, message: str, problem: Any = None, starts: list[Any] | None = None) -> None:
        super().__init__(message)
        self.problem = problem
        self.starts = starts or []


class Interrupted(SpringBalanceError):
    """The user stopped a solve (Ctrl-C).

    Attributes:
        problem: the :class:`~springbalance.design.problem.DesignProblem` being solved.
        starts: the records of the starts that had finished.
        total: how many starts the multi-start had.
        best_x: the best feasible design found so far (variables of ``problem``), or None.
    """

    def __init__(
        self,
        message: str,
        problem: Any = None,
        starts: Iterable[Any] | None = None,
        total: int = 0,
        best_x: np.ndarray | None = None,
    ) -> None:
        super().__init__(message)
        self.problem = problem
        self.starts = list(starts or [])
        self.total = int(total)
        self.best_x = best_x
