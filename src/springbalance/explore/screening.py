r"""The fewest-springs search of a spatial study: screen the topologies of each spring count on the exact
coefficients, solve only what the screen finds.

On an arm of revolute joints with zero-free-length springs (the spatial reachability test applies,
:class:`~springbalance.explore.topology.SpatialTest`), a study is a search for the **fewest** springs that
balance exactly with their anchors inside the candidates' boxes. Spring counts go up from 1; per count:

1. **Proofs.** The topologies the reachability test proves unreachable are counted (never screened).
2. **Screen.** Every other topology is screened, those that add one spring to the best screened topologies of
   the count below first (:meth:`Search.prior`), by :func:`~springbalance.design.exact.anchor_fit.fit_anchors`:
   ``screen`` anchor sets drawn in the boxes (seed: the study's ``seed`` and the topology), ``k ≥ 0`` fitted by
   non-negative least squares, then anchors and stiffnesses refined together on the exact multilinear
   coefficients (3ⁿ grid values projected on the few coefficients springs can reach), anchors kept in their
   boxes and ``k`` in the law's bounds. A topology whose largest coefficient left is below
   :data:`SCREEN_EXACT` of gravity's largest is an exact design; the count's screen stops there.
3. **Solve.** The exact topology is solved as a task like any other (its design record, report and design
   file), from the screened anchors and stiffnesses as its one start (``init`` in its boxes), and so verified
   on the study's samples. A count without one solves its ``approximate`` best-screened topologies the same
   way, for the count's best approximate design (marked ``screened`` in the report).
4. The search **stops** at the first count with an exact design.

A topology screened without reaching exactness is **not found**, not proven impossible: the fit is local
and starts from a few draws. The summary (``study.json`` ``screening``, the report, the command's summary)
keeps the two apart per count: proven unreachable, screened (not found), exact.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import json
import time
from typing import Any, Iterable, Sequence

from threadpoolctl import threadpool_limits

from springbalance.design.exact.anchor_fit import MAX_JOINTS, AnchorFit, CoefficientSystem, SpringEnds, fit_anchors
from springbalance.errors import InputError
from springbalance.explore.candidates import Candidate
from springbalance.explore.elimination import ELIMINATE_ABOVE, eliminate
from springbalance.explore.execution import progress_bar
from springbalance.explore.task import EXACT, Task
from springbalance.explore.topology import SpatialTest, Verdict
from springbalance.model.mechanism import Mechanism

#: anchor draws per topology unless ``explore.screen`` says otherwise (0: no screen, every topology solved)
DEFAULT_DRAWS = 4
#: a screened topology is exact when its largest coefficient left is below this fraction of gravity's
SCREEN_EXACT = EXACT * 1e-3
#: the keys a spring law may have for the screen (its potential is then k L²/2 and linear in k)
_LAW_KEYS = {"type", "stiffness"}


@dataclasses.dataclass
class CountScreen:
    """What the search found at one spring count."""

    count: int
    topologies: int
    unreachable: int
    screened: int = 0
    exact: list[str] = dataclasses.field(default_factory=list)
    best: list[str] = dataclasses.field(default_factory=list)
    best_relative: float = float("nan")
    seconds: float = 0.0
    #: the exact design came from elimination (an upper bound: this count and the ones up to it not screened)
    eliminated: bool = False

    @property
    def not_found(self) -> int:
        """Screened without reaching exact balance (not proven impossible)."""
        return self.screened - (1 if self.exact and not self.eliminated else 0)

    def describe(self) -> str:
        """One line: proven, screened, found."""
        head = f"{self.count} spring(s): {self.topologies} topologies, {self.unreachable} proven unreachable, "
        if self.eliminated:
            return head + (
                f"not screened: exact with {len(self.exact)} springs by elimination from every candidate (an upper "
                f"bound): {' + '.join(self.exact)}"
            )
        if self.exact:
            return head + f"exact after screening {self.screened}: {' + '.join(self.exact)}"
        found = f"; best coefficient residual {self.best_relative:.3g} of gravity's" if self.best else ""
        return head + f"{self.not_found} screened without exact balance (not found, not proven){found}"

    def to_dict(self) -> dict[str, Any]:
        return {**dataclasses.asdict(self), "not_found": self.not_found, "summary": self.describe()}


def _stiffness_bounds(law: dict) -> tuple[float, float] | None:
    """``(lower, upper)`` [N/m] of the law's free stiffness, or None when the screen does not apply."""
    if law.get("type") != "zero_free_length" or not set(law) <= _LAW_KEYS:
        return None
    stiffness = law.get("stiffness")
    if not isinstance(stiffness, dict) or "lower" not in stiffness or "upper" not in stiffness:
        return None
    lower, upper = stiffness["lower"], stiffness["upper"]
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (lower, upper)):
        return None
    return (float(lower), float(upper)) if 0 <= lower < upper else None


class Search:
    """The fewest-springs search of one study (module documentation)."""

    def __init__(
        self,
        mechanism: Mechanism,
        candidates: Sequence[Candidate],
        verdicts: dict[tuple[int, ...], Verdict],
        bounds: tuple[float, float],
        draws: int,
        seed: int,
        test: SpatialTest | None = None,
    ):
        self.mechanism, self.candidates, self.verdicts, self.test = mechanism, list(candidates), verdicts, test
        self._system: CoefficientSystem | None = None
        self.bounds, self.draws, self.seed = bounds, draws, seed
        self.fits: dict[tuple[int, ...], AnchorFit] = {}
        self.counts: dict[int, CountScreen] = {}
        #: per count screened, its exact topology (None: not found; of another count when found by elimination)
        self.found: dict[int, tuple[int, ...] | None] = {}
        #: what elimination gave (None: nothing exact, or not tried: ``_tried``)
        self.eliminated: tuple[tuple[int, ...], AnchorFit] | None = None
        self._tried = False

    @property
    def system(self) -> CoefficientSystem:
        """The arm's coefficient system (built on the first screen: a few seconds for six joints)."""
        if self._system is None:
            self._system = CoefficientSystem(self.mechanism)
        return self._system

    @classmethod
    def of(cls, layout: Any, law: dict, explore: dict, seed: int, prune: bool, label: str) -> Search | None:
        """The search of a study's layout, or None when it does not apply (a planar or non-revolute arm, a law
        other than a zero-free-length spring with free stiffness, ``prune: false``, ``screen: 0``, or a grid
        that sweeps the mechanism). InputError naming ``label`` for a bad ``explore.screen``."""
        draws = explore.get("screen", DEFAULT_DRAWS)
        if isinstance(draws, bool) or not isinstance(draws, int) or draws < 0:
            raise InputError(
                f"{label}: explore.screen must be an integer ≥ 0 (anchor draws per topology), got {draws!r}"
            )
        grid = explore.get("grid") or {}
        bounds = _stiffness_bounds(law)
        if (
            not isinstance(layout.test, SpatialTest)
            or bounds is None
            or not prune
            or not draws
            or not isinstance(grid, dict)
            or any(str(key).split(".")[0] == "mechanism" for key in grid)
            or layout.mechanism.nv > MAX_JOINTS
        ):
            return None
        return cls(layout.mechanism, layout.candidates, layout.verdicts, bounds, draws, seed, layout.test)

    def ends(self, topology: Iterable[int]) -> list[SpringEnds]:
        """The candidates of a topology as springs to fit."""
        return [SpringEnds(c.a, c.box_a, c.b, c.box_b) for c in (self.candidates[i] for i in topology)]

    def fit(self, topology: tuple[int, ...]) -> AnchorFit:
        """The screen of one topology (cached)."""
        if topology not in self.fits:
            self.fits[topology] = fit_anchors(
                self.system, self.ends(topology), self.bounds, self.draws, [self.seed, *topology], SCREEN_EXACT * 1e-3
            )
        return self.fits[topology]

    def screen(
        self, count: int, tasks: Sequence[Task], topologies: Sequence[tuple[int, ...]], show: bool
    ) -> CountScreen:
        """Screen the unproven topologies of ``count`` springs, in order, until one is exact (a count whose every
        topology is proven unreachable: the pruned ones among ``tasks``, for an approximate design)."""
        clock = time.perf_counter()
        level = [topology for topology in topologies if len(topology) == count]
        open_ = sorted((topology for topology in level if topology not in self.verdicts), key=self.prior)
        result = CountScreen(count, len(level), len(level) - len(open_))
        queue = open_ or list(dict.fromkeys(task.topology for task in tasks if task.count == count))
        progress = progress_bar(len(queue), show, f"screening {count} spring(s)")
        self.found[count] = None
        with threadpool_limits(limits=1):  # BLAS threads only contend on the fit's small matrices
            eliminated = self._eliminate(show) if len(open_) > ELIMINATE_ABOVE else None
            if eliminated is not None:  # exact by elimination: this count and those up to it are not screened
                self.fits[eliminated[0]], self.found[count] = eliminated[1], eliminated[0]
                result.exact, result.eliminated, queue = self.labels(eliminated[0]), True, []
                result.best, result.best_relative = result.exact, eliminated[1].relative
            for topology in queue:
                fit = self.fit(topology)
                result.screened += 1 if open_ else 0  # a proven topology fitted for a design is not "not found"
                progress.update(1)
                if not result.best or fit.relative < result.best_relative:
                    result.best, result.best_relative = self.labels(topology), fit.relative
                if fit.relative <= SCREEN_EXACT and open_:
                    result.exact, self.found[count] = self.labels(topology), topology
                    break
        progress.close()
        result.seconds = time.perf_counter() - clock
        self.counts[count] = result
        return result

    def _eliminate(self, show: bool) -> tuple[tuple[int, ...], AnchorFit] | None:
        """Elimination, tried once (:mod:`springbalance.explore.elimination`): its exact design, or None."""
        if not self._tried:
            self._tried, test = True, self.test

            def proven(topology: tuple[int, ...]) -> bool:
                return topology in self.verdicts or (test is not None and test.verdict(topology) is not None)

            options = (self.bounds, self.draws, self.seed)
            self.eliminated = eliminate(
                self.system, self.ends(range(len(self.candidates))), proven, options, SCREEN_EXACT, show
            )
        return self.eliminated

    def prior(self, topology: tuple[int, ...]) -> float:
        """The screening order: the best residual of the topology's screened subsets of one spring fewer (a
        topology that completes a nearly exact one comes first); ties keep the enumeration's order."""
        subsets = (topology[:i] + topology[i + 1 :] for i in range(len(topology)))
        return min((self.fits[subset].relative for subset in subsets if subset in self.fits), default=float("inf"))

    def labels(self, topology: Sequence[int]) -> list[str]:
        return [self.candidates[index].label for index in topology]

    def tasks(self, count: int, tasks: Sequence[Task], approximate: int) -> list[Task]:
        """The tasks to solve at ``count`` after its screen (:meth:`screen`): the exact topology's, or the
        ``approximate`` best-screened ones; each from its screened design (module documentation)."""
        exact = self.found.get(count)
        if exact is not None:
            chosen = [exact]
        else:
            screened = [topology for topology in self.fits if len(topology) == count]
            chosen = sorted(screened, key=lambda topology: self.fits[topology].relative)[:approximate]
        if exact is not None and len(exact) != count:  # by elimination: a topology of another count
            return [self._started(self._task(template, exact), self.fits[exact], False) for template in tasks[:1]]
        return [
            self._started(task, self.fits[task.topology], exact is None)
            for topology in chosen
            for task in tasks
            if task.topology == topology
        ]

    def _task(self, template: Task, topology: tuple[int, ...]) -> Task:
        """A task of ``topology`` like ``template`` (its config and grid point, the same law for every spring)."""
        record = copy.deepcopy(template.record)
        law = {key: value for key, value in record["springs"][0].items() if key not in ("name", "a", "b")}
        record["springs"] = [
            {**copy.deepcopy(law), "name": f"s{number + 1}", "a": a, "b": b}
            for number, (a, b) in enumerate(self.candidates[index].anchors() for index in topology)
        ]
        return Task("", topology, tuple(self.labels(topology)), template.grid, record, "")

    def _started(self, task: Task, fit: AnchorFit, approximate: bool) -> Task:
        """``task`` with its springs starting at the screened design (``init`` of each box and stiffness)."""
        record = copy.deepcopy(task.record)
        for spring, (z_a, z_b), k in zip(record["springs"], fit.anchors, fit.stiffness):
            spring["a"]["box"]["init"] = [float(v) for v in z_a]
            spring["b"]["box"]["init"] = [float(v) for v in z_b]
            spring["stiffness"] = {**spring["stiffness"], "init": float(k)}
        screened = f"screened: best coefficient residual {fit.relative:.3g} of gravity's"
        pruned = (task.pruned or screened) if approximate else ""  # a proven topology keeps its verdict
        digest = hashlib.sha256(json.dumps({"record": record, "screened": True}, sort_keys=True).encode())
        return Task(digest.hexdigest()[:16], task.topology, task.labels, task.grid, record, pruned)

    def summary(self) -> dict[str, Any]:
        """Per spring count screened: proven, screened, exact (``study.json`` ``screening``)."""
        return {str(count): result.to_dict() for count, result in sorted(self.counts.items())}


def faced(topologies: Sequence[tuple[int, ...]], verdicts: dict[tuple[int, ...], Verdict]) -> list[str]:
    """Per spring count, one line: how many topologies and how many proven unreachable (before any solve)."""
    lines = []
    for count in sorted({len(topology) for topology in topologies}):
        level = [topology for topology in topologies if len(topology) == count]
        proven = sum(1 for topology in level if topology in verdicts)
        lines.append(
            f"  {count} spring(s): {len(level)} topologies, {proven} proven unreachable, {len(level) - proven} left"
        )
    return lines
