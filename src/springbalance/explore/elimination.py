r"""An exact design by elimination, when a spring count has too many topologies to screen one by one.

The fewest-springs search (:mod:`springbalance.explore.screening`) screens every unproven topology of a
count. On an arm whose gravity has many coefficients (a UR5 with its centres of mass off the axes: 38 of
them, against 7 on the stock UR5) the minimum lies near ten springs, and the counts on the way hold
thousands of topologies each. Before such a count (more than :data:`ELIMINATE_ABOVE` unproven topologies)
the search first tries **elimination**:

1. fit one spring per candidate, all at once (anchors in their boxes, stiffnesses in the law's bounds,
   :func:`~springbalance.design.exact.anchor_fit.fit_anchors`): with many springs exact balance is easy to reach;
2. if that is exact, drop springs one at a time, weakest first, each time refitting the rest from the
   current design (a warm start), and keep a drop whenever the rest stays exact;
3. stop when no spring can be dropped.

The result is an exact design and so an **upper bound** on the fewest springs, not the minimum: the counts
between the last one screened and the design's are reported as not screened.
"""

from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from springbalance.design.exact.anchor_fit import AnchorFit, CoefficientSystem, SpringEnds, fit_anchors
from springbalance.explore.execution import progress_bar

#: a count with more unproven topologies than this is not screened before an elimination is tried
ELIMINATE_ABOVE = 1000
#: residual evaluations of one draw of a fit with many springs
EVALUATIONS = 400


def eliminate(
    system: CoefficientSystem,
    candidates: Sequence[SpringEnds],
    proven: Callable[[tuple[int, ...]], bool],
    fit_options: tuple[tuple[float, float], int, int],
    exact: float,
    show: bool,
) -> tuple[tuple[int, ...], AnchorFit] | None:
    """The topology (candidate indices) and fit an elimination ends with (module documentation), or None when
    the full set is proven unreachable (``proven``) or its fit is not exact (below ``exact`` of gravity's largest
    coefficient). ``fit_options``: the stiffness bounds [N/m], the draws of the first fit and the seed."""
    bounds, draws, seed = fit_options
    current = tuple(range(len(candidates)))
    if proven(current):
        return None

    def fit(topology: tuple[int, ...], tries: int, start: AnchorFit | None) -> AnchorFit:
        ends = [candidates[i] for i in topology]
        return fit_anchors(
            system, ends, bounds, tries, [seed, len(topology), *topology], exact * 1e-3, EVALUATIONS, start
        )

    best = fit(current, draws, None)
    if best.relative > exact:
        return None
    bar = progress_bar(len(current), show, "eliminating springs")
    dropped = True
    while dropped:
        dropped = False
        for index in np.argsort(best.stiffness):  # the weakest spring first
            trial = current[:index] + current[index + 1 :]
            if not trial or proven(trial):
                continue
            keep = [i for i in range(len(current)) if i != index]
            found = fit(trial, 2, AnchorFit(best.relative, [best.anchors[i] for i in keep], best.stiffness[keep], 0))
            if found.relative <= exact:
                current, best, dropped = trial, found, True
                bar.update(1)
                break
    bar.close()
    return current, best
