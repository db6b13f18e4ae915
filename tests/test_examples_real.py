"""The shipped real-arm examples run as a newcomer runs them, from the command line on a clone.

``springbalance design examples/<arm>.yaml --out d.json`` must exit 0 with no failure section in its
report, save a design whose clearance fit converged, cut the RMS torque of the gravity-loaded joints by
at least the floors below, and ``springbalance clearance d.json --samples N`` (N = 10 × the config's
``clearance.check_samples``, poses the fit never saw) must find no spring closer than the margin.

The floors are not this test's own output. They come from other runs of the same problems
(docs/developer/performance.md#real-arms), less an allowance:

- UR5 (examples/ur5.yaml, 256 poses, 4 starts, four coils with a 10⁶-cycle duty, at most 1.4 kg; 2026-11-26,
  after a clearance round that stops infeasible falls back): solve seeds 0-4 cut the shoulder lift by 76.17 /
  76.15 / 76.15 / 76.23 / 76.14 % and the elbow by 41.72 / 41.80 / 41.68 / 41.64 / 41.81 %, each exit 0
  (benchmarks/bench_real.py --cases example-ur5 --parts c; 4× the starts: 76.18 / 41.72 %); after the
  coils' length rules and body stresses were searched to the joint limits, 76.21 / 76.06 / 76.14 / 76.03 /
  76.17 % and 41.64 / 43.12 / 41.74 / 43.34 / 41.69 % (seeds 1, 0, 2, 3, 4; 1 ships); at 512 poses
  1.2 kg of coils cut 75.1 / 38.2 % and 1.6 kg 77.0 / 44.3 %. In the environment constraints.txt pins (2026-11-28)
  seeds 1 (the shipped one), 0, 2, 4 cut 75.61 / 76.04 / 75.47 / 75.94 % and 41.75 / 43.23 / 42.11 / 43.20 %, and
  seed 3 fails its verification (74.86 / 35.84 %, exit 3). With the shoulder's boxes kept above the table
  (2026-11-28, session 57) seeds 1, 0, 2, 3, 4 cut 75.85 / 76.04 / 75.79 / 75.79 / 75.79 % and 42.59 / 43.23 /
  42.63 / 42.63 / 42.63 %, each exit 0, and 1.2 kg of coils 74.23 / 40.18 %. Kept 5 mm above the table too
  (``mechanism.floor: 0``; without it the coils hung up to 0.3 m below the table at some poses), seeds 1, 0, 2,
  3, 4 cut 74.93 / 74.97 / 75.02 / 74.93 / 75.01 % and 40.73 / 40.98 / 40.70 / 40.73 / 40.70 %, each exit 0
  (bench_real --cases example-ur5 --parts abc; 4× the starts 74.96 / 40.94 %), and 1.2 kg of coils 73.47 /
  37.50 %. The floors, 73 % and 38.5 %, sit about 2 points below the worst seed, so a platform whose rounding
  lands on another of these optima still passes, while a broken pipeline does not (before the fall-back, seed 2
  ended at 72.4 / 37.5 % and ``worse_joint``: its ideal twin's fit to the arm kept a round that had stopped
  infeasible, objective 6.17 instead of 0.087, and the rows of that fit held the coils). The ceiling, from
  physics: ideal springs (no coil limits) in the same boxes, kept as clear, reach 97.6 % and 93.9 %, and no coil
  design can beat its ideal twin, a relaxation of the same problem (checked on the objective the solve
  minimises).
- Panda (examples/panda.yaml, 256 poses, 8 starts, three coils with a 10⁶-cycle duty, 1.2 kg): solve seeds
  0 / 1 / 2 cut joint 2 by 81.9 / 81.7 / 81.9 % and joint 4 by 68.4 / 68.3 / 68.4 % (2026-11-26, after issue
  28's fatigue rule; seed 1 ended 7 µN outside its fatigue floor row, see docs/developer/performance.md);
  the floors, 78 % and 64 %, sit below the worst. The ceiling, from physics: each spring spans one joint
  (link 1 → 2, link 3 → 4),
  so joint 2's spring torque is a function of joint 2's angle alone and joint 4's of joint 4's alone, while
  gravity about each depends on both (the forearm's angle to the vertical). The best function of one angle,
  fitted to the gravity torque over the example's ranges (4,096 Sobol poses), cuts 81.7 % and 67.9 %; ideal
  springs in the same boxes, kept clear, reach 81.8 % and 68.2 % at the example's 256 poses.

A clean example (``CLEAN``) must also report none of the findings of issue 27 part 5 (a weak design, heavy
springs, a range beyond the joint limits, a spring inside its own link, a wire off the series, a joint made
worse, a rule broken at unseen poses) nor a coil short of its fatigue life (``short_life``, issue 28), and
pass its own verification at unseen poses. ``BOUNDED`` examples bound their coils' mass (``max_spring_mass``)
to at most 4× the floor of docs/model.md §5.1 and a tenth of the arm's moving mass (the UR5's 1.4 kg is 3.96×
its floor of 0.354 kg and 8.2 % of 17.0 kg); the test checks both on the design's own mass record, so that no
``heavy_springs`` is not an accident of rounding. One exception remains, ``HEAVY`` (the Panda): the floor
counts the energy per kilogram of the thinnest wire, while music wire that lives 10⁶ cycles exchanges 205 J/kg
at 0.1 mm but 80.7 J/kg at 2.5 mm and 70.4 J/kg at 4 mm (index 10; spring_mass.coil_energy_per_kg times
fatigue_energy_fraction), and an extension coil's hooks bind before its body, so the Panda's 1.2 kg weighs
more than the 4× of the floor at which ``heavy_springs`` warns; its bound is at most a tenth of the arm's
moving mass, which the test checks, so that the warning can only be the floor's. ``UNCHANGED`` lists
joints that must carry the same torque as without springs: the Panda's joints 3, 5, 6 and 7, which no spring
spans; the coils' own weight hangs on links 1-4, but the elbow coil lies in the arm's plane, where it has no
moment about joint 3 (held at 0).

No two springs may run through each other: each example keeps them apart (``clearance.between_springs``), and
the design's verification at unseen poses measures every pair too (its ``clearance`` rules).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from springbalance.loaders import load_yaml
from springbalance.results.result import DesignResult
from springbalance.viz.browser import find_chromium

ROOT = Path(__file__).resolve().parents[1]
TIMEOUT = 1200  # [s] one design on a loaded 2-core machine with an empty compile cache
#: where the examples' reports and the screenshots of their scenes are kept (a build artefact to look at)
PICTURES = ROOT / "out" / "examples"

#: the RMS cut [%] each example must at least reach on its gravity-loaded joints (see the module docstring)
FLOORS = {
    "ur5.yaml": {"shoulder_lift_joint": 73.0, "elbow_joint": 38.5},
    "panda.yaml": {"panda_joint2": 78.0, "panda_joint4": 64.0},
}
#: examples that must report no finding of issue 27 part 5 and pass their verification at unseen poses
CLEAN = {"panda.yaml", "ur5.yaml"}
#: examples whose ``max_spring_mass`` keeps their coils within 4× the floor and a tenth of the arm (module docstring)
BOUNDED = {"ur5.yaml"}
#: examples whose coils outweigh 4× the floor, bounded to a tenth of the arm's moving mass (module docstring)
HEAVY = {"panda.yaml"}
#: the findings of issue 27 part 5 a clean example must not report (failures or warnings)
PART5 = {
    "infeasible",
    "not_converged",
    "unbuildable",
    "overlap",
    "partial",
    "worse_joint",
    "not_verified",
    "weak_design",
    "heavy_springs",
    "beyond_joint_limits",
    "inside_own_link",
    "off_series_wire",
    "short_life",
}
#: joints whose RMS and peak torque the example's springs must leave as they are (see the module docstring)
UNCHANGED = {"panda.yaml": ("panda_joint3", "panda_joint5", "panda_joint6", "panda_joint7")}


def springbalance(*args: str) -> subprocess.CompletedProcess:
    """``springbalance ARGS`` from the repository root, as a newcomer types it."""
    return subprocess.run(
        [sys.executable, "-m", "springbalance", *args],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(FLOORS))
def test_example_designs_and_stays_clear(name: str, tmp_path: Path) -> None:
    config = Path("examples") / name
    out = tmp_path / "d.json"
    run = springbalance("design", str(config), "--out", str(out))
    assert run.returncode == 0, f"{config}: exit {run.returncode}\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}"
    assert "Traceback" not in run.stderr
    assert "Failures" not in run.stdout, run.stdout[-3000:]

    record = json.loads(out.read_text())
    fit = record["solver"]["fit"]
    assert fit["converged"], f"{config}: the clearance fit did not converge: {fit}"
    rows = {row["joint"]: row for row in DesignResult.load(out).metrics()["joints"]}
    for joint, floor in FLOORS[name].items():
        cut = rows[joint]["rms_reduction_percent"]
        assert cut >= floor, f"{config}: {joint} RMS cut {cut:.2f} % < {floor} %"
    for joint in UNCHANGED.get(name, ()):
        for key in ("rms", "peak"):
            before, after = rows[joint][f"{key}_before"], rows[joint][f"{key}_after"]
            assert after == pytest.approx(before, rel=1e-9, abs=1e-9), f"{config}: {joint} {key} {before} → {after}"
    settings = load_yaml((ROOT / config).read_text())
    assert settings["clearance"].get("between_springs"), f"{config}: springs not kept apart from each other"
    if "floor" in settings["mechanism"]:  # the table is saved with the design, so the check below keeps it
        assert record["mechanism"]["floor"] == settings["mechanism"]["floor"], record["mechanism"]
    assert all(spring.get("duty") for spring in settings["springs"]), f"{config}: a coil states no duty"
    if name in CLEAN:
        allowed = {"heavy_springs"} if name in HEAVY else set()
        found = sorted({finding["kind"] for finding in record["warnings"]} & (PART5 - allowed))
        assert not found, f"{config}: reports {found}: {record['warnings']}"
        verification = record["solver"]["verification"]
        assert verification["passed"], verification
        pairs = {rule["spring"] for rule in verification["rules"] if rule["rule"] == "clearance"}
        assert pairs == {spring["name"] for spring in settings["springs"]}, verification["rules"]
    if name in HEAVY:  # the bound holds and is at most a tenth of the arm: heavy_springs can only be the floor's 4×
        mass = DesignResult.load(out).spring_mass()
        assert mass.total <= settings["max_spring_mass"] * (1 + 1e-6), mass
        assert settings["max_spring_mass"] <= 0.1 * mass.arm_moving_mass, mass
    if name in BOUNDED:
        # the bound holds, and the coils weigh at most 4× the floor and a tenth of the arm (no heavy_springs)
        mass = DesignResult.load(out).spring_mass()
        assert mass.total <= settings["max_spring_mass"] * (1 + 1e-6), mass
        assert mass.total <= 4 * mass.floor and mass.total <= 0.1 * mass.arm_moving_mass, mass
        # a relaxation cannot be beaten: the coils' objective is no better than their ideal twin's
        twin = record["solver"]["twin"]
        assert record["metrics"]["objectives"][record["objective"]]["after"] >= twin["objective"], twin

    settings = settings["clearance"]
    poses = 10 * settings["check_samples"]
    check = springbalance("clearance", str(out), "--samples", str(poses))
    assert check.returncode == 0, check.stderr
    names = {spring["name"] for spring in record["springs"]}
    rows = [line.split() for line in check.stdout.splitlines() if line.split()[:1] and line.split()[0] in names]
    assert len(rows) == len(names), check.stdout
    for row in rows:  # spring, radius [mm], clearance [mm], closest link, status, ...
        assert float(row[2]) >= 1e3 * settings["margin"], f"{config}: {' '.join(row[:5])} at {poses} poses"
        assert row[4] == "ok", check.stdout
    assert f"over {poses} poses" in check.stdout
    _keep_pictures(config, out)


def _keep_pictures(config: Path, design: Path) -> None:
    """Write the example's report to ``out/examples/<name>/`` and a screenshot of its scene next to it, as a
    person would open them; the scene must show the arm and the springs (``python -m springbalance.viz.browser``)."""
    folder = PICTURES / config.stem
    report = springbalance("report", str(design), "--out", str(folder))
    assert report.returncode == 0, report.stderr[-3000:]
    if find_chromium() is None:
        return  # the browser's own tests say why they skip; the report is kept all the same
    check = subprocess.run(
        [sys.executable, "-m", "springbalance.viz.browser", str(folder / "scene.html"), "--screenshot",
         str(PICTURES / f"{config.stem}.png")],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert check.returncode == 0 and "PASSED" in check.stdout, check.stdout + check.stderr
