r"""A study: every spring topology (× every point of a parameter grid) solved as a task on Dask.

A study config is a design config (``mechanism``, ``workspace``, ``objective``, ``solve``, ...)
whose ``springs`` section is replaced by ``explore``::

    explore:
      candidates: auto             # or [[body_a, body_b], ...] or [{a: {body, box}, b: {body, box}}, ...]
      span: 2                      # auto: joints a spring may cross between two moving bodies
      margin: 0.05                 # auto: growth [m] of a body's collision bounding box
      default_box: 0.3             # half-width [m] of an end's box on a body without collision geometry
      max_springs: 3
      spring: {type: zero_free_length, stiffness: {lower: 0, upper: 5000}}   # the law of every spring
      starts: 4                    # multi-start of each topology (default: the solve section's)
      seed: 0
      grid: {objective: [rms, peak], "workspace.n": [64, 128]}   # optional sweep: dotted keys -> values
      prune: true                  # skip the topologies that cannot balance exactly (false: solve them too,
                                   # for the best approximate design of each spring count)
      approximate: 3               # per spring count that pruning leaves without a topology: solve this many
                                   # of its pruned ones for its best approximate design (0: none)
      reports: true                # write each solved design's report (designs/<id>/report.html)
      max_topologies: 20000        # a larger study is refused before it is enumerated
      screen: 4                    # spatial arms: anchor draws per topology of the fewest-springs search
                                   # (explore.screening; 0: solve every topology that is not pruned)

Each task is one topology at one grid point: a pure function of its record
(:func:`~springbalance.explore.task.solve_task`), so the same task gives the same result on any
worker. Tasks run on **Dask distributed** (:mod:`springbalance.explore.execution`): a
``LocalCluster`` with one worker process per core by default, or any cluster by its scheduler address. They are submitted by spring count, so that a topology whose
subset already balances exactly is not solved (dominance, :mod:`springbalance.explore.topology`).

**The study folder.** ``study.json`` holds the study's fingerprint (a hash of the config, without
``max_springs``), the candidates and the pruning. Each finished task is written at once, atomically,
to ``results/<id>.json`` (``<id>``: a hash of the task's record), and ``results.csv`` is rewritten
after each. Running the same command again resumes: the tasks whose result files exist are not
solved again. A folder that holds another config's study is refused unless ``force`` (which starts
it afresh). At the end, ``report.html`` (:mod:`springbalance.explore.report`), the best design of
each spring count, ``best_<k>_springs.json`` (a design file every command accepts), and each solved
design's file and report under ``designs/`` (:mod:`springbalance.explore.designs`) are written.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import itertools
import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from springbalance.deprecation import moved_names
from springbalance.errors import InputError
from springbalance.explore import execution as _execution
from springbalance.explore import task as _task
from springbalance.explore.approximate import DEFAULT as DEFAULT_APPROXIMATE
from springbalance.explore.approximate import approximate_topologies
from springbalance.explore.candidates import (
    DEFAULT_HALF_WIDTH,
    DEFAULT_MARGIN,
    Candidate,
    auto_candidates,
    candidates_from_records,
)
from springbalance.explore.designs import write_designs
from springbalance.explore.execution import (  # noqa: F401  (make_client: see _MOVED)
    ProgressBar,
    execute,
    make_client,
    progress_bar,
)
from springbalance.explore.folder import claim_folder, finished_results
from springbalance.explore.pseudo_base_proposals import proposals_for
from springbalance.explore.report import write_study_report
from springbalance.explore.screening import Search
from springbalance.explore.table import COLUMNS, results_csv  # noqa: F401  (COLUMNS: importable from here)
from springbalance.explore.task import Task
from springbalance.explore.topology import (
    MAX_TOPOLOGIES,
    Reachability,
    SpatialTest,
    Verdict,
    enumerate_topologies,
    reachability,
)
from springbalance.files import write_json_atomic, write_text_atomic
from springbalance.io.config import config_from_dict, mechanism_from_dict, read_config_file
from springbalance.model.mechanism import Mechanism
from springbalance.pipeline.state import checked_seeds

if TYPE_CHECKING:
    from distributed import Client

#: keys of the ``explore`` section
EXPLORE_KEYS = (
    "candidates",
    "span",
    "margin",
    "default_box",
    "max_springs",
    "spring",
    "starts",
    "seed",
    "grid",
    "prune",
    "approximate",
    "reports",
    "max_topologies",
    "screen",
)
#: names that moved out of this module: where they live now (each still importable from here, with a
#: DeprecationWarning, for one release). ``make_client`` (now :mod:`springbalance.explore.execution`) is
#: still imported above without a warning while the command line imports it from here.
_MOVED = {"EXACT": _task, "solve_task": _task, "CONNECT_TIMEOUT": _execution}


__getattr__ = moved_names(__name__, {name: (module, name) for name, module in _MOVED.items()})


@dataclasses.dataclass
class Layout:
    """One mechanism's candidates, its topologies and the verdicts of its pruning."""

    mechanism: Mechanism
    candidates: list[Candidate]
    note: str
    topologies: list[tuple[int, ...]]
    verdicts: dict[tuple[int, ...], Verdict]
    test: Reachability | SpatialTest | None = None


def _fingerprint(record: Any) -> str:
    return hashlib.sha256(json.dumps(record, sort_keys=True, default=str).encode()).hexdigest()[:16]


def _set_dotted(record: dict, key: str, value: object, where: str) -> None:
    """Set ``a.b.c`` in a nested mapping (the grid's overrides)."""
    parts = key.split(".")
    node = record
    for part in parts[:-1]:
        if not isinstance(node.get(part), dict):
            node[part] = {}
        node = node[part]
    node[parts[-1]] = value


def _switches(explore: dict, label: str) -> tuple[bool, int, bool]:
    """``prune``, ``approximate`` and ``reports`` of the ``explore`` section, checked."""
    prune, reports = explore.get("prune", True), explore.get("reports", True)
    for key, value in (("prune", prune), ("reports", reports)):
        if not isinstance(value, bool):
            raise InputError(f"{label}: explore.{key} must be true or false, got {value!r}")
    approximate = explore.get("approximate", DEFAULT_APPROXIMATE)
    if isinstance(approximate, bool) or not isinstance(approximate, int) or approximate < 0:
        raise InputError(f"{label}: explore.approximate must be an integer ≥ 0, got {approximate!r}")
    return prune, approximate, reports


class Study:
    """A study read from a config (see the module documentation)."""

    def __init__(self, record: dict, base_dir: str | Path = ".", label: str = "study", max_springs: int | None = None):
        if not isinstance(record, dict):
            raise InputError(f"{label}: expected a mapping with the sections of a design config and 'explore'")
        if "springs" in record:
            raise InputError(f"{label}: springs: a study finds the springs itself; give an 'explore' section instead")
        explore = record.get("explore")
        if not isinstance(explore, dict):
            raise InputError(f"{label}: missing section 'explore' (candidates, max_springs, spring, ...)")
        unknown = [key for key in explore if key not in EXPLORE_KEYS]
        if unknown:
            raise InputError(f"{label}: explore: unknown key {unknown[0]!r}; valid keys: {', '.join(EXPLORE_KEYS)}")
        seeds = (record.get("solve") or {}).get("seeds")
        #: each topology solved at each of these seeds, its best design kept (None: at ``seed`` alone)
        self.seeds = None if seeds is None else checked_seeds(seeds, f"{label}: solve.seeds")
        self.label, self.base_dir = label, Path(base_dir)
        self.base = {key: value for key, value in record.items() if key != "explore"}
        self.explore = {**explore, **({} if max_springs is None else {"max_springs": max_springs})}  # --max-springs
        self.max_springs = self.explore.get("max_springs", 2)
        if isinstance(self.max_springs, bool) or not isinstance(self.max_springs, int) or self.max_springs < 1:
            raise InputError(
                f"{label}: explore.max_springs (--max-springs) must be an integer ≥ 1, got {self.max_springs!r}"
            )
        law = self.explore.get("spring", {"type": "zero_free_length", "stiffness": {"lower": 0.0, "upper": 5000.0}})
        if not isinstance(law, dict) or any(key in law for key in ("a", "b", "name", "joint", "path")):
            raise InputError(
                f"{label}: explore.spring: the law of every spring, a spring record without name and ends, got {law!r}"
            )
        self.law = law
        self.starts = self.explore.get("starts", (self.base.get("solve") or {}).get("starts", 4))
        self.seed = self.explore.get("seed", (self.base.get("solve") or {}).get("seed", (self.seeds or [0])[0]))
        for key, value in (("starts", self.starts), ("seed", self.seed)):
            if isinstance(value, bool) or not isinstance(value, int) or value < (1 if key == "starts" else 0):
                raise InputError(
                    f"{label}: explore.{key} must be an integer ≥ {1 if key == 'starts' else 0}, got {value!r}"
                )
        if "mechanism" not in self.base:
            raise InputError(f"{label}: missing section 'mechanism'")
        self.margin = self.explore.get("margin", DEFAULT_MARGIN)
        self.default_box = self.explore.get("default_box", DEFAULT_HALF_WIDTH)
        for key, value in (("margin", self.margin), ("default_box", self.default_box)):
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not value >= 0:
                raise InputError(f"{label}: explore.{key} must be a number ≥ 0 [m], got {value!r}")
        self.prune, self.approximate, self.reports = _switches(self.explore, label)
        self.limit = self.explore.get("max_topologies", MAX_TOPOLOGIES)
        if isinstance(self.limit, bool) or not isinstance(self.limit, int) or self.limit < 1:
            raise InputError(f"{label}: explore.max_topologies must be an integer ≥ 1, got {self.limit!r}")
        self._layouts: dict[str, Layout] = {}
        layout = self._layout(self.base["mechanism"])  # the base mechanism's (a grid may sweep others)
        self.mechanism, self.candidates, self.reachability_note = layout.mechanism, layout.candidates, layout.note
        self.topologies, self.verdicts = layout.topologies, layout.verdicts
        self.search = Search.of(layout, self.law, self.explore, self.seed, self.prune, label)
        self.grid = self._grid(self.explore.get("grid") or {})
        self.fingerprint = _fingerprint(
            {**self.base, "explore": {k: v for k, v in self.explore.items() if k != "max_springs"}}
        )
        self.tasks = [task for point in self.grid for task in self._tasks(point)]
        # a config error (a bad grid value, a bad law) shows here, not on a worker
        if self.tasks:
            config_from_dict(self.tasks[0].record, self.base_dir, f"{label} (task {self.tasks[0].id})")

    # ---------------------------------------------------------------- tasks
    def _layout(self, mechanism_record: Any) -> Layout:
        """The candidates, topologies and pruning of one mechanism (a grid may sweep robots)."""
        key = json.dumps(mechanism_record, sort_keys=True, default=str)
        if key not in self._layouts:
            label = self.label
            mechanism = mechanism_from_dict(mechanism_record, self.base_dir, f"{label}: mechanism")
            candidates = self.explore.get("candidates", "auto")
            try:
                if candidates == "auto":
                    found = auto_candidates(mechanism, self.explore.get("span", 2), self.margin, self.default_box)
                else:
                    found = candidates_from_records(mechanism, candidates, self.margin, self.default_box)
            except InputError as error:
                raise InputError(f"{label}: {error}") from None
            test, note = reachability(mechanism, found, self.law.get("type", "extension"))
            topologies = enumerate_topologies(len(found), self.max_springs, self.limit)
            verdicts = {}
            if test is not None:
                for topology in topologies:
                    verdict = test.verdict(topology)
                    if verdict is not None:
                        verdicts[topology] = verdict
            self._layouts[key] = Layout(mechanism, found, note, topologies, verdicts, test)
        return self._layouts[key]

    def _grid(self, grid: object) -> list[dict[str, Any]]:
        if not isinstance(grid, dict):
            raise InputError(f"{self.label}: explore.grid: expected a mapping of dotted config keys to lists of values")
        keys = list(grid)
        for key in keys:
            if not isinstance(grid[key], list) or not grid[key]:
                raise InputError(f"{self.label}: explore.grid.{key}: expected a non-empty list of values")
            if key.split(".")[0] in ("explore", "springs"):
                raise InputError(
                    f"{self.label}: explore.grid.{key}: a grid sweeps the design config, not {key.split('.')[0]!r}"
                )
        return [dict(zip(keys, values)) for values in itertools.product(*(grid[key] for key in keys))] or [{}]

    def _tasks(self, point: dict[str, Any]) -> list[Task]:
        base = copy.deepcopy(self.base)
        for key, value in point.items():
            _set_dotted(base, key, copy.deepcopy(value), key)
        layout = self._layout(base.get("mechanism"))
        tasks = []
        approximate = (
            approximate_topologies(layout.topologies, layout.verdicts, layout.test, self.approximate)
            if self.prune
            else []
        )
        for topology in layout.topologies:
            if self.prune and topology in layout.verdicts and topology not in approximate:
                continue
            springs = []
            for number, index in enumerate(topology):
                a, b = layout.candidates[index].anchors()
                springs.append({**copy.deepcopy(self.law), "name": f"s{number + 1}", "a": a, "b": b})
            record = {**base, "springs": springs}
            labels = tuple(layout.candidates[index].label for index in topology)
            task_id = _fingerprint({"record": record, "starts": self.starts, "seed": self.seed})
            verdict = layout.verdicts.get(topology) if self.prune else None
            pruned = f"{verdict.kind}: {verdict.reason}" if verdict else ""
            tasks.append(Task(task_id, topology, labels, point, record, pruned))
        return tasks

    def summary(self) -> dict[str, Any]:
        """The enumeration and its pruning, as saved in ``study.json``."""
        total = len(self.topologies)
        orderings = sum(math.factorial(len(topology)) for topology in self.topologies)
        by_kind: dict[str, list] = {}
        for topology, verdict in self.verdicts.items():
            by_kind.setdefault(verdict.kind, []).append(
                {"springs": [self.candidates[index].label for index in topology], "reason": verdict.reason}
            )
        return {
            "candidates": [{"label": c.label, **c.to_dict()} for c in self.candidates],
            "topologies": total,
            "orderings": orderings,
            "grid_points": len(self.grid),
            "reachability": self.reachability_note,
            "unreachable": by_kind.get("unreachable", []),
            "degenerate": by_kind.get("degenerate", []),
            "tasks": len(self.tasks),
            **({"screening": self.search.summary()} if self.search is not None else {}),
        }

    # ---------------------------------------------------------------- running
    def pending(self, folder: str | Path) -> int:
        """How many tasks have no result in ``folder`` yet (0: a run has nothing to solve)."""
        results = Path(folder) / "results"
        return sum(1 for task in self.tasks if not (results / f"{task.id}.json").exists())

    def run(
        self,
        folder: str | Path,
        client: Client | None = None,
        force: bool = False,
        progress: bool = True,
        on_result: Callable[[dict], None] | None = None,
    ) -> StudyResult:
        """Solve every task not solved yet (see the module documentation); ``client`` is a Dask
        ``Client`` (None: one after another in this process)."""
        folder = Path(folder)
        results_dir = folder / "results"
        self._claim(folder, force)
        done = finished_results(results_dir)
        resumed, total = sum(1 for task in self.tasks if task.id in done), len(self.tasks)
        solved: list[str] = []
        dominated: list[dict] = []
        bar = progress_bar(0 if self.search else len(self.tasks) - resumed, progress)
        for count in range(1, self.max_springs + 1):
            level = self._level(count, done, dominated, bar)
            if self.search is not None:  # the fewest-springs search: screen, then solve what it found
                level = [task for task in self.tasks if task.count == count]
                self.search.screen(count, level, self.topologies, progress)
                level = self.search.tasks(count, level, self.approximate)
                self.tasks.extend(level)
                level = [task for task in level if task.id not in done]
            starts = 1 if self.search else self.starts
            for record in execute(level, client, self.base_dir, starts, self.seed, self.seeds):
                write_json_atomic(results_dir / f"{record['id']}.json", record)
                done[record["id"]] = record
                solved.append(record["id"])
                self._write_table(folder, done)
                bar.update(1)
                if on_result is not None:
                    on_result(record)
            if self.search is not None and self.search.found.get(count) is not None:
                break  # the fewest springs that balance exactly
        bar.close()
        resumed += sum(1 for task in self.tasks[total:] if task.id in done and task.id not in solved)  # screened ones
        result = StudyResult(
            self, folder, {task.id: done[task.id] for task in self.tasks if task.id in done}, dominated, solved, resumed
        )
        result.write()
        return result

    def _level(self, count: int, done: dict, dominated: list[dict], bar: ProgressBar) -> list[Task]:
        """The tasks of ``count`` springs to solve: not done, and no subset balances exactly (those are added to
        ``dominated``)."""
        level = []
        for task in self.tasks:
            if task.count != count or task.id in done:
                continue
            exact = [
                other
                for other in self.tasks
                if other.count < count
                and other.grid == task.grid
                and set(other.topology) < set(task.topology)
                and done.get(other.id, {}).get("exact")
            ]
            if exact:
                dominated.append(
                    {"id": task.id, "springs": list(task.labels), "grid": task.grid, "because": list(exact[0].labels)}
                )
                bar.update(1)
                continue
            level.append(task)
        return level

    def _claim(self, folder: Path, force: bool) -> None:
        """Make ``folder`` this study's (:func:`~springbalance.explore.folder.claim_folder`)."""
        claim_folder(
            folder, self.fingerprint, {"config": {**self.base, "explore": self.explore}, **self.summary()}, force
        )

    def _write_table(self, folder: Path, done: dict) -> None:
        rows = [done[task.id] for task in self.tasks if task.id in done]
        write_text_atomic(folder / "results.csv", results_csv(rows))


@dataclasses.dataclass
class StudyResult:
    """What a run of a study leaves: every task's result by id, and what was skipped."""

    study: Study
    folder: Path
    results: dict[str, dict]
    dominated: list[dict]
    solved: list[str]
    resumed: int

    def best(self) -> dict[int, dict]:
        """The solved task with the smallest relative residual, per spring count (over the grid)."""
        best: dict[int, dict] = {}
        for record in self.results.values():
            if record.get("status") != "solved":
                continue
            count = record["count"]
            if count not in best or record["relative_residual"] < best[count]["relative_residual"]:
                best[count] = record
        return dict(sorted(best.items()))

    def exact(self) -> list[dict]:
        """The results that balance exactly."""
        return [record for record in self.results.values() if record.get("exact")]

    def write(self) -> None:
        """``best_<k>_springs.json`` per spring count, each solved design's file and report (``designs/``,
        :mod:`springbalance.explore.designs`), the dominance in ``study.json``, and ``report.html``."""
        for count, record in self.best().items():
            write_json_atomic(self.folder / f"best_{count}_springs.json", record["design"])
        links = write_designs(self.folder, self.results, self.study.reports)
        marker = self.folder / "study.json"
        summary = json.loads(marker.read_text(encoding="utf-8"))
        summary.update(dominated=self.dominated, pseudo_base_proposals=proposals_for(self))
        summary.update({"screening": self.study.search.summary()} if self.study.search is not None else {})
        write_json_atomic(marker, summary)
        write_study_report(
            self.folder,
            self.study.mechanism.name,
            {**self.study.summary(), "pseudo_base_proposals": summary["pseudo_base_proposals"]},
            self.study.max_springs,
            self.results,
            self.dominated,
            self.best(),
            links,
            self.study.approximate,
        )


# ---------------------------------------------------------------------- entry points
def load_study(path: str | Path, max_springs: int | None = None) -> Study:
    """A :class:`Study` from a study config file (YAML or JSON)."""
    path = Path(path)
    record = read_config_file(path)
    return Study(record, path.parent, str(path), max_springs=max_springs)
