"""Ctrl-C during ``springbalance design``: a clean stop (exit 130, one line that says which starts
had finished, no file), and with ``--partial`` the best design of the finished starts saved.

The command runs as a real process that receives a real SIGINT while it works through 100,000
starts of a small problem (far more than it can finish before the signal).
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from cli_helpers import default_ctrl_c
from springbalance.results.result import DesignResult

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.slow  # a real Ctrl-C to a solving process, after 6 s of its CPU time


def _config(tmp_path) -> Path:
    path = tmp_path / "slow.yaml"
    path.write_text(f"""
mechanism: {{urdf: {ROOT / "urdf" / "two_link_planar.urdf"}}}
workspace: {{kind: sobol, n: 64}}
springs:
  - {{name: s1, type: zero_free_length, a: {{body: universe, box: {{lower: [-0.1, 0, 0.1], upper: [0.1, 0, 0.4]}}}},
      b: {{body: link1, box: {{lower: [0.1, 0, -0.05], upper: [0.5, 0, 0.05]}}}}, stiffness: {{lower: 0, upper: 5000}}}}
solve: {{starts: 100000, workers: 1}}
""")
    return path


def _cpu_seconds(pid: int) -> float:
    """User + system CPU time [s] of process ``pid`` (Linux /proc)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _sigint_state(pid: int) -> dict[str, bool]:
    """Whether SIGINT is blocked, ignored or caught in process ``pid`` (Linux /proc)."""
    fields = dict(line.split(":", 1) for line in Path(f"/proc/{pid}/status").read_text().splitlines() if ":" in line)
    bit = 1 << (signal.SIGINT - 1)
    return {key: bool(int(fields[key].strip(), 16) & bit) for key in ("SigBlk", "SigIgn", "SigCgt")}


def _interrupt(tmp_path, *extra) -> tuple[int, str, Path]:
    out = tmp_path / "design.json"
    process = subprocess.Popen(
        [sys.executable, "-m", "springbalance", "design", str(_config(tmp_path)), "--out", str(out), *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "SPRINGBALANCE_WORKERS": "1"},
        preexec_fn=default_ctrl_c,
    )
    # start-up, compile and some starts: wait for 6 s of the process's own CPU time (not wall time, which a
    # loaded machine stretches), at most 120 s
    deadline = time.monotonic() + 120.0
    while _cpu_seconds(process.pid) < 6.0 and time.monotonic() < deadline:
        assert process.poll() is None, process.communicate()
        time.sleep(0.2)
    assert process.poll() is None, process.communicate()
    process.send_signal(signal.SIGINT)
    try:
        _, err = process.communicate(timeout=60)
    finally:  # a process that outlives the test is killed, not left behind
        if process.poll() is None:
            process.kill()
            process.communicate()
    return process.returncode, err, out


@pytest.mark.parametrize("partial", [False, True])
def test_ctrl_c_stops_cleanly_and_partial_saves_the_best_so_far(tmp_path, partial):
    code, err, out = _interrupt(tmp_path, *(["--partial"] if partial else []))
    assert code == 130
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    match = re.search(r"interrupted: (\d+) of 100000 starts had finished", lines[0])
    assert match, lines[0]
    finished = int(match.group(1))
    assert 1 <= finished < 100000
    assert "starts 0 (" in lines[0] and "best objective" in lines[0]  # the finished starts, and the best
    if partial:
        assert out.exists() and "saved to" in lines[0]
        result = DesignResult.load(out)
        assert result.metrics()["objectives"]["rms"]["reduction_percent"] > 50  # a real design, not the start
        saved = json.loads(out.read_text())
        assert len(saved["solver"]["starts"]) == finished and saved["solver"]["method"] == "interrupted"
        # marked as not finished: the file says so, and the loaded design fails with `partial`
        assert saved["partial"] is True and saved["partial_reason"].startswith("interrupted")
        assert "partial" in [record["kind"] for record in saved["failures"]] and not result.ok
    else:
        assert not out.exists() and "nothing is saved" in lines[0]
        assert not list(tmp_path.glob(".design.json*"))  # no temporary file left either
