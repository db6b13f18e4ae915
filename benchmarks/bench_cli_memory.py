"""Peak memory of a design through the command line, per sample: `springbalance design` as a user runs it.

Problem: the UR5 with the 4 ideal extension springs of bench_memory.py (anchors in ±0.3 m boxes, stiffness and
free length free, no tension constraint), rms objective, one start, written as a config file at each --samples
size. Each size runs the command in a fresh process; its peak resident memory is read with
``resource.getrusage(RUSAGE_CHILDREN)`` in a fresh parent per run, so that only that command counts. The figure
is the growth between the smallest and the largest size divided by the samples added [KiB per sample]
(goal ≤ 4 KiB: the config check, the kinematics, the data of the samples, the solve, the report and the saved
file together).

Run: .venv/bin/python benchmarks/bench_cli_memory.py [--samples 1024 65536]   (about a minute on 2 cores)
"""

import argparse
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, nargs="+", default=[1024, 65536])
args = parser.parse_args()

PAIRS = [
    ("universe", "upper_arm_link"),
    ("universe", "forearm_link"),
    ("upper_arm_link", "forearm_link"),
    ("shoulder_link", "forearm_link"),
]
BOX = "{lower: [-0.3, -0.3, -0.3], upper: [0.3, 0.3, 0.3]}"
SPRING = (
    "  - {{type: extension, ideal: true, keep_tension: false, stiffness: {{lower: 0, upper: 5000}}, "
    "free_length: {{lower: 0.05, upper: 1.0}}, a: {{body: {a}, box: {box}}}, b: {{body: {b}, box: {box}}}}}"
)
MEASURE = textwrap.dedent("""
    import resource, subprocess, sys
    subprocess.run([sys.executable, "-m", "springbalance", "design", sys.argv[1], "--out", sys.argv[2], "--quiet"],
                   check=True)
    print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)   # KiB (Linux)
""")


def peak_kib(folder: Path, samples: int) -> int:
    config = folder / f"ur5_{samples}.yaml"
    springs = "\n".join(SPRING.format(a=a, b=b, box=BOX) for a, b in PAIRS)
    config.write_text(
        f"mechanism: {{robot: ur5}}\nworkspace: {{kind: sobol, n: {samples}, seed: 1}}\n"
        f"springs:\n{springs}\nsolve: {{starts: 1, workers: 1}}\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", MEASURE, str(config), str(folder / f"design_{samples}.json")],
        capture_output=True,
        text=True,
        check=True,
    )
    return int(done.stdout.split()[-1])


with tempfile.TemporaryDirectory() as name:
    peaks = {samples: peak_kib(Path(name), samples) for samples in sorted(args.samples)}
for samples, peak in peaks.items():
    print(f"{samples:7d} samples: peak {peak / 1024:7.1f} MiB")
low, high = min(peaks), max(peaks)
print(f"growth: {(peaks[high] - peaks[low]) / (high - low):.2f} KiB per sample from {low} to {high} samples (goal ≤ 4)")
