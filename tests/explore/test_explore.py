"""Studies (springbalance explore): topologies found and pruned, solved on a real Dask LocalCluster.

The exact-balance facts come from the literature on zero-free-length balancing of planar chains
(docs/model.md §9): for a three-link chain, ground→link 2, ground→link 3 and link 1→link 3
balance exactly, while ground→link 1, link 1→link 2 and link 2→link 3 never can (no spring
reaches the weight moment of link 2 and beyond from the ground). The distributed runs use a
real ``LocalCluster`` with two worker processes.
"""

from __future__ import annotations

import json
import os
import signal
import time
from pathlib import Path

import pytest
import yaml

from springbalance.cli import main
from springbalance.explore import load_study, make_client, solve_task
from springbalance.results.result import DesignResult
from study_report_helpers import assert_links_resolve

pytestmark = pytest.mark.slow  # every test here runs a whole study

ROOT = Path(__file__).resolve().parents[2]
THREE_LINK = ROOT / "examples" / "explore_three_link.yaml"
EXACT = 1e-6


def small_study(tmp_path, **explore) -> Path:
    """The two-link arm, every candidate (prune off), two objectives: 12 small tasks."""
    config = {
        "mechanism": {"urdf": str(ROOT / "urdf" / "two_link_planar.urdf")},
        "workspace": {"kind": "sobol", "n": 32, "seed": 0},
        "explore": {
            "candidates": "auto",
            "span": 1,
            "max_springs": 2,
            "prune": False,
            "starts": 2,
            "seed": 3,
            "spring": {"type": "zero_free_length", "stiffness": {"lower": 0, "upper": 5000}},
            "grid": {"objective": ["rms", "pe_variance"]},
            "reports": False,  # no page per design: these tests are about solving
            **explore,
        },
    }
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def _comparable(record: dict) -> str:
    """A result without its timings (the design's numbers stay), as JSON text (NaN compares equal)."""
    design = record.get("design") or {}
    return json.dumps(
        {
            "row": {key: value for key, value in record.items() if key not in ("seconds", "design")},
            "variables": design.get("variables"),
            "metrics": design.get("metrics"),
        },
        sort_keys=True,
    )


@pytest.fixture(scope="module")
def cluster_client():
    client = make_client(workers=2)
    yield client
    cluster = client.cluster
    client.close()
    cluster.close()


# ---------------------------------------------------------------------- must-hold 1
def test_three_link_chain_exact_topology_found_and_unreachable_ones_listed(tmp_path):
    study = load_study(THREE_LINK)
    result = study.run(tmp_path / "study", progress=False)
    best = result.best()[3]
    assert best["relative_residual"] < EXACT and best["exact"]
    assert set(best["springs"]) == {"universe→link2", "universe→link3", "link1→link3"}
    assert best["buildable"] is False  # ideal zero-free-length springs: no coil spec sheet says they can be wound
    summary = json.loads((tmp_path / "study" / "study.json").read_text())
    unreachable = [set(item["springs"]) for item in summary["unreachable"]]
    assert {"universe→link1", "link1→link2", "link2→link3"} in unreachable  # the chain of neighbours
    # the best design is a design file like any other
    loaded = DesignResult.load(tmp_path / "study" / "best_3_springs.json")
    assert loaded.exact_balance()["relative_residual"] < EXACT
    assert main(["evaluate", str(tmp_path / "study" / "best_3_springs.json")]) == 0
    assert "Pareto" in (tmp_path / "study" / "report.html").read_text()
    # pruning leaves no 1- or 2-spring topology: the report still gives each count's best approximate design,
    # the best of a few pruned topologies solved anyway, whose residual is not exact
    for count in (1, 2):
        approximate = [r for r in result.results.values() if r["count"] == count]
        assert 1 <= len(approximate) <= study.approximate and all(r["pruned"] for r in approximate)
        assert not result.best()[count]["exact"] and result.best()[count]["relative_residual"] > 1e-3
    assert_links_resolve(tmp_path / "study")
    # every pruned topology really is worse: solving the neighbour chain leaves a residual
    unpruned = load_study(THREE_LINK, max_springs=3)
    unpruned.prune = False
    chain = next(
        task for task in unpruned._tasks({}) if set(task.labels) == {"universe→link1", "link1→link2", "link2→link3"}
    )
    record = solve_task(
        {
            "id": chain.id,
            "labels": list(chain.labels),
            "grid": {},
            "record": chain.record,
            "base_dir": str(THREE_LINK.parent),
            "starts": 2,
            "seed": 0,
        }
    )
    assert record["relative_residual"] > 1e-3


# ---------------------------------------------------------------------- must-hold 2
def test_sequential_and_distributed_studies_are_identical(tmp_path, cluster_client):
    config = small_study(tmp_path)
    sequential = load_study(config).run(tmp_path / "sequential", progress=False)
    distributed = load_study(config).run(tmp_path / "distributed", client=cluster_client, progress=False)
    assert len(sequential.results) == 12 and set(sequential.results) == set(distributed.results)
    for key in sequential.results:
        assert _comparable(sequential.results[key]) == _comparable(distributed.results[key]), key
    # the grid swept both objectives
    assert {record["objective"] for record in distributed.results.values()} == {"rms", "pe_variance"}
    # the tasks ran on the workers, not here
    assert len(cluster_client.scheduler_info()["workers"]) == 2


# ---------------------------------------------------------------------- must-hold 3
def test_a_killed_worker_does_not_lose_the_study_and_resume_solves_nothing_twice(tmp_path, cluster_client):
    config = small_study(tmp_path, seed=5)
    study = load_study(config)
    killed = []

    def kill_one_worker(record):
        if not killed:
            pids = cluster_client.run(os.getpid)
            victim = sorted(pids.values())[0]
            os.kill(victim, signal.SIGKILL)
            killed.append(victim)

    result = study.run(tmp_path / "study", client=cluster_client, progress=False, on_result=kill_one_worker)
    assert killed
    assert len(result.results) == 12 and all(record["status"] == "solved" for record in result.results.values())
    assert len(list((tmp_path / "study" / "results").glob("*.json"))) == 12
    # the nanny restarts the worker; a resume then finds every task done
    again = load_study(config).run(tmp_path / "study", client=cluster_client, progress=False)
    assert again.solved == [] and again.resumed == 12
    # an interrupted study (files of some tasks removed) solves only those
    for path in sorted((tmp_path / "study" / "results").glob("*.json"))[:3]:
        path.unlink()
    partial = load_study(config).run(tmp_path / "study", progress=False)
    assert len(partial.solved) == 3 and partial.resumed == 9


# ---------------------------------------------------------------------- must-hold 5: bad input
def test_bad_study_input_gets_one_line(tmp_path, capsys):
    config = small_study(tmp_path)
    out = tmp_path / "out"

    def fails(argv, expected):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert expected in err, err
        assert "Traceback" not in err and len(err.strip().splitlines()) == 1

    clock = time.perf_counter()
    fails(
        ["explore", str(config), "--out", str(out), "--scheduler", "tcp://127.0.0.1:9", "--timeout", "2"],
        "cannot reach the Dask scheduler at 'tcp://127.0.0.1:9' within 2 s",
    )
    assert time.perf_counter() - clock < 30
    fails(["explore", str(config), "--out", str(out), "--max-springs", "0"], "--max-springs")
    bad = yaml.safe_load(config.read_text())
    bad["explore"]["candidates"] = [["universe", "link9"]]
    (tmp_path / "bad.yaml").write_text(yaml.safe_dump(bad))
    fails(["explore", str(tmp_path / "bad.yaml"), "--out", str(out)], "unknown body 'link9'")
    # a folder holding another config's study is refused unless --force
    assert main(["explore", str(config), "--out", str(out), "--sequential", "--quiet"]) == 0
    other = yaml.safe_load(config.read_text())
    other["workspace"]["n"] = 16
    (tmp_path / "other.yaml").write_text(yaml.safe_dump(other))
    before = sorted(path.name for path in (out / "results").iterdir())
    fails(
        ["explore", str(tmp_path / "other.yaml"), "--out", str(out), "--sequential"],
        "holds the results of a different config",
    )
    assert sorted(path.name for path in (out / "results").iterdir()) == before
    assert main(["explore", str(tmp_path / "other.yaml"), "--out", str(out), "--sequential", "--quiet", "--force"]) == 0
    assert sorted(path.name for path in (out / "results").iterdir()) != before
