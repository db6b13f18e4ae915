"""The two-link demo's solve with its coils' fatigue duty against the same demo without it, in one run.

examples/two_link.yaml states ``duty: {cycles: 1e6}`` on each coil (docs/model.md §3.8.2): two more design
variables per coil (bounds of its force), two more rows per sample and three once. This times ``springbalance.solve`` of the config as shipped
and of the same config with every ``duty`` removed (the static rules only), alternating, ``--repeats`` times
each after one warm-up of each (compiled functions cached), and prints the medians of the wall time and of
the CPU time (this process and its worker processes, which a loaded machine inflates less than the wall
time), their ratios and the objectives.

Run: .venv/bin/python benchmarks/bench_demo.py [--repeats 3]   (make bench-demo; about a minute)
"""

from __future__ import annotations

import argparse
import resource
import statistics
import time
from pathlib import Path

import yaml

import springbalance as sb
from springbalance.io.config import config_from_dict

ROOT = Path(__file__).resolve().parents[1]
DEMO = ROOT / "examples" / "two_link.yaml"


def configs() -> dict:
    """The demo as shipped ("with duty") and without its coils' duty ("static rules")."""
    record = yaml.safe_load(DEMO.read_text(encoding="utf-8"))
    static = yaml.safe_load(DEMO.read_text(encoding="utf-8"))
    for spring in static["springs"]:
        spring.pop("duty", None)
    base = DEMO.parent
    return {
        "with duty": config_from_dict(record, base_dir=base, label=str(DEMO)),
        "static rules": config_from_dict(static, base_dir=base, label=f"{DEMO} without duty"),
    }


def cpu_seconds() -> float:
    """CPU time [s] of this process and of its finished child processes (the solves' worker pools)."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    cases = configs()
    seconds: dict[str, list[float]] = {name: [] for name in cases}
    cpu: dict[str, list[float]] = {name: [] for name in cases}
    objectives: dict[str, float] = {}
    for round_ in range(args.repeats + 1):  # round 0 warms the compile cache
        for name, config in cases.items():
            clock, cpu_clock = time.perf_counter(), cpu_seconds()
            result = sb.solve(config, progress=False)
            if round_:
                seconds[name].append(time.perf_counter() - clock)
                cpu[name].append(cpu_seconds() - cpu_clock)
            objectives[name] = float(result.metrics()["objectives"]["rms"]["after"])
    for name in cases:
        print(
            f"{name:14s} median {statistics.median(seconds[name]):6.2f} s (CPU {statistics.median(cpu[name]):6.2f} s)"
            f"  objective {objectives[name]:.10g}"
        )
    ratio = statistics.median(seconds["with duty"]) / statistics.median(seconds["static rules"])
    cpu_ratio = statistics.median(cpu["with duty"]) / statistics.median(cpu["static rules"])
    print(f"with duty / static rules: ×{ratio:.2f} (CPU ×{cpu_ratio:.2f})")


if __name__ == "__main__":
    main()
