"""Studies: find where springs should go (candidate topologies, pruned, each solved as a Dask task).

:mod:`~springbalance.explore.candidates` (where a spring may go), :mod:`~springbalance.explore.topology`
(which sets of candidates, and which cannot balance exactly), :mod:`~springbalance.explore.task` (one
topology at one grid point, solved by a pure function), :mod:`~springbalance.explore.execution` (where
the tasks run: here or on Dask), :mod:`~springbalance.explore.approximate` (which pruned topologies to solve
for a count's best approximate design), :mod:`~springbalance.explore.study` (the study, its folder, resuming),
:mod:`~springbalance.explore.table` (results.csv), :mod:`~springbalance.explore.designs` (each design's file
and report), :mod:`~springbalance.explore.pareto` (the Pareto plot) and :mod:`~springbalance.explore.report`
(report.html).
"""

from springbalance.explore.candidates import Candidate, auto_candidates, candidates_from_records
from springbalance.explore.execution import make_client
from springbalance.explore.study import Study, StudyResult, load_study
from springbalance.explore.task import solve_task
from springbalance.explore.topology import Reachability, enumerate_topologies

__all__ = [
    "Candidate",
    "Reachability",
    "Study",
    "StudyResult",
    "auto_candidates",
    "candidates_from_records",
    "enumerate_topologies",
    "load_study",
    "make_client",
    "solve_task",
]
