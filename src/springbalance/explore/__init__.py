"""Studies: find where springs should go (candidate topologies, pruned, each solved as a Dask task).

:mod:`~springbalance.explore.candidates` (where a spring may go), :mod:`~springbalance.explore.topology`
(which sets of candidates, and which cannot balance exactly), :mod:`~springbalance.explore.study` (the
tasks on Dask, the study folder, resuming) and :mod:`~springbalance.explore.report` (report.html).
"""

from springbalance.explore.candidates import Candidate, auto_candidates, candidates_from_records
from springbalance.explore.study import Study, StudyResult, load_study, make_client, solve_task
from springbalance.explore.topology import Reachability, enumerate_topologies

__all__ = ["Candidate", "Reachability", "Study", "StudyResult", "auto_candidates", "candidates_from_records",
           "enumerate_topologies", "load_study", "make_client", "solve_task"]
