r"""The side of each link a design clear of the arm passes on (:func:`side_rows`), as rows another solve keeps.

A fit to the arm's rows hold a spring clear only at the poses they watch: those where the rounds found it too
close. A design solved inside them from elsewhere (the coils, from their ideal twin's fitted design) can pass
on the other side of a link, through it at some pose no row watches, and its own fit must then move it back
through the link. :func:`side_rows` holds it on the side it passes now: for every spring and every collision
object it is checked against (and every other spring, with ``between_springs``), the separating plane at the
pair's closest pose of the check set, as the fit's rows are built (:mod:`springbalance.design.clearance`): both
ends of the spring beyond the plane through the witness point ``w`` with normal ``n``,

.. math:: n^\top (E_e(x) - w) - r - m^+ \ge 0, \qquad e \in \{a, b\}.

Far pairs give loose rows; the near ones fix the side. A row the design itself breaks (a pair between the
margin and the rows' target distance) is left out. One pose a pair: on the UR5 with four 40 mm coils
(bench_real ur5-coils-clear) the coils' fit then ended at 0.88 N·m RMS; with each pair's two or four closest
poses the coils' multi-start was held tighter and the fit ended at 1.08 and 1.28 N·m, and with up to eight poses
of the pairs within 3 cm of the margin (most pairs then have none) at 1.32 N·m.
"""

from __future__ import annotations

import numpy as np

from springbalance.design.clearance import LinearRows
from springbalance.design.clearance_fit import _Checker
from springbalance.design.clearance_rows import _rows, rows_held
from springbalance.design.problem import DesignProblem


def side_rows(problem: DesignProblem, x: np.ndarray) -> LinearRows | None:
    """The rows that hold every spring of ``problem`` (with its clearance) on the side of each link it passes on
    at design ``x`` [physical units], at each pair's closest pose of the check set (see the module documentation);
    None when the problem has no clearance or no row holds at ``x``."""
    clearance = problem.clearance
    if clearance is None:
        return None
    x = np.asarray(x, dtype=float)
    checker = _Checker(problem, clearance)
    _, _, nearest = checker.measure(x, 0)
    keys = [pair + (pose_set, sample) for pair, poses in nearest.items() for _, pose_set, sample in poses[:1]]
    object_cuts, spring_cuts = checker.cuts(x, keys)
    rows = rows_held(problem, _rows(problem, x, object_cuts, spring_cuts, None), x)
    if rows is None:
        return None
    labels = [f"{label}, the side it passes on" for label in rows.labels]
    return LinearRows(rows.names, rows.matrix, rows.offset, labels, rows.scale)
