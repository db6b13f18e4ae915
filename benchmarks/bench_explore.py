"""A UR5 topology study on a Dask LocalCluster against the same study one task after another.

Study: the UR5 from example-robot-data, ``candidates: auto`` with span 1 (the ground to each of the
six moving links, and each link to the next: 11 candidates), up to 2 zero-free-length springs per
topology (11 + 55 = 66 topologies; ``screen: 0`` solves every one not proven unreachable, not the fewest-springs search), each solved
with a --starts multi-start (default 2) on a --samples (default 512) Sobol workspace. Run twice in this process, into two
fresh study folders:

  - sequential: Study.run(client=None), every task here, one after another;
  - distributed: Study.run on a LocalCluster of --workers worker processes (default: one per core),
    started before the clock (its start-up is printed on its own).

Each run starts from an empty compile cache of its own (SPRINGBALANCE_CACHE_DIR), so neither
reuses the other's compiled residuals. Both give the same results (checked: every task's
objective equal). Prints the wall times and
the speed-up (the issue's goal: ≥ 1.6× on 2 cores).

Run: .venv/bin/python benchmarks/bench_explore.py [--starts 2] [--samples 512] [--workers N]   (make bench-explore)
"""

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

import yaml

from springbalance.explore import load_study, make_client


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=2)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--samples", type=int, default=512)
    args = parser.parse_args()

    folder = Path(tempfile.mkdtemp(prefix="bench-explore-"))
    config = folder / "ur5_study.yaml"
    config.write_text(
        yaml.safe_dump(
            {
                "mechanism": {"robot": "ur5"},
                "workspace": {"kind": "sobol", "n": args.samples, "seed": 1},
                "explore": {
                    "candidates": "auto",
                    "span": 1,
                    "max_springs": 2,
                    "starts": args.starts,
                    "seed": 0,
                    "spring": {"type": "zero_free_length", "stiffness": {"lower": 0, "upper": 5000}},
                    "reports": False,  # the benchmark times the solves, not the 66 designs' pages
                    "screen": 0,  # every topology solved (not the fewest-springs search): the Dask speed-up
                },
            }
        )
    )
    study = load_study(config)
    print(
        f"UR5 study: {len(study.candidates)} candidates, {len(study.tasks)} topologies (≤ 2 springs), "
        f"{args.starts} start(s) each, {args.samples} samples; {os.cpu_count()} cores"
    )

    # each run compiles its residuals afresh (an empty compile cache of its own), so neither gains from
    # the other's compiled code; the cluster's workers inherit the variable when they start
    os.environ["SPRINGBALANCE_CACHE_DIR"] = str(folder / "cache-sequential")
    clock = time.perf_counter()
    sequential = load_study(config).run(folder / "sequential", progress=False)
    t_sequential = time.perf_counter() - clock
    print(f"sequential:  {t_sequential:7.1f} s  ({t_sequential / len(study.tasks):.2f} s per topology)")

    os.environ["SPRINGBALANCE_CACHE_DIR"] = str(folder / "cache-distributed")
    clock = time.perf_counter()
    client = make_client(workers=args.workers)
    t_startup = time.perf_counter() - clock
    workers = len(client.scheduler_info()["workers"])
    clock = time.perf_counter()
    distributed = load_study(config).run(folder / "distributed", client=client, progress=False)
    t_distributed = time.perf_counter() - clock
    cluster = client.cluster
    client.close()
    cluster.close()
    print(
        f"distributed: {t_distributed:7.1f} s on a LocalCluster of {workers} worker processes "
        f"(+ {t_startup:.1f} s to start it)"
    )
    same = all(
        json.dumps(sequential.results[key].get("objective_value"))
        == json.dumps(distributed.results[key].get("objective_value"))
        for key in sequential.results
    )
    print(
        f"speed-up: ×{t_sequential / t_distributed:.2f} (×{t_sequential / (t_distributed + t_startup):.2f} with the "
        f"cluster's start-up); results identical: {same}"
    )
    best = distributed.best()
    for count, record in best.items():
        print(
            f"  best with {count} spring(s): {' + '.join(record['springs'])}, residual "
            f"{record['relative_residual']:.3g} of the unbalanced peak"
        )


if __name__ == "__main__":  # the worker processes of the cluster import this file again
    main()
