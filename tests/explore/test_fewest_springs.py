"""The fewest-springs search of a spatial study (springbalance.explore.screening, design.exact.anchor_fit).

The arm is tests/spatial_helpers.py's yaw–pitch–roll arm with link 3's centre of mass 5 cm off the roll
axis; its gravity potential, derived by hand there, is

    V_g = const − g (M2 C2 + M3 (L2 + C3)) sin θ₂ + g M3 offset cos θ₂ sin θ₃.

A zero-free-length spring's potential depends only on the joints between its two bodies, so the
cos θ₂ sin θ₃ term needs a spring that crosses the pitch *and* the roll. Of the six ``auto`` candidates
(the ground to each link, each link to the next two) only ground→link3 and link1→link3 do: 4 of the
C(6,1) = 6 one-spring topologies, and the C(4,2) = 6 two-spring topologies built from the other four,
are proven unreachable; the rest are screened.

Every design the search reports exact is checked independently of the code: the holding torque is the
central difference of the potential computed by Pinocchio alone (``computePotentialEnergy`` plus
``k L²/2`` per spring, physics_helpers.ReferencePotential) at random poses, against Pinocchio's gravity
torque.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import yaml

import springbalance as sb
from physics_helpers import ReferencePotential, RefSpring
from spatial_helpers import WEIGHT_MOMENT, G, H, yaw_pitch_roll, yaw_pitch_roll_urdf
from springbalance.cli import main
from springbalance.design.exact.anchor_fit import CoefficientSystem, SpringEnds, fit_anchors
from springbalance.errors import InputError
from springbalance.explore.candidates import auto_candidates
from springbalance.explore.elimination import eliminate
from springbalance.explore.screening import Search
from springbalance.explore.study import Study
from springbalance.explore.topology import SpatialTest, enumerate_topologies


def _worst_torque_ratio(mechanism: sb.Mechanism, springs: list[dict], poses: int = 10, seed: int = 3) -> float:
    """Largest |τ| of gravity plus ``springs`` (design-file records) at random poses, relative to the largest
    gravity torque there (finite differences of Pinocchio's potential)."""
    model = mechanism.model
    reference = ReferencePotential(
        model,
        [
            RefSpring(
                s["a"]["body"],
                tuple(s["a"]["point"]),
                s["b"]["body"],
                tuple(s["b"]["point"]),
                s["k"],
                zero_free_length=True,
            )
            for s in springs
        ],
    )
    rng, data, h = np.random.default_rng(seed), model.createData(), 1e-5
    worst = scale = 0.0
    for _ in range(poses):
        angles = rng.uniform(-np.pi, np.pi, mechanism.nv)
        tau = [
            (
                reference(mechanism.configurations(angles + h * e)[0])
                - reference(mechanism.configurations(angles - h * e)[0])
            )
            / (2 * h)
            for e in np.eye(mechanism.nv)
        ]
        worst = max(worst, float(np.max(np.abs(tau))))
        gravity = pin.computeGeneralizedGravity(model, data, mechanism.configurations(angles)[0])
        scale = max(scale, float(np.max(np.abs(gravity))))
    return worst / scale


def _springs(design: dict) -> list[dict]:
    """The design file's springs at the optimum (its ``design`` section: fixed points and stiffness)."""
    return [{"a": spring["a"], "b": spring["b"], "k": float(spring["stiffness"])} for spring in design["design"]]


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """The study run by the command (``springbalance explore --sequential``): its printout and its folder."""
    folder = tmp_path_factory.mktemp("fewest")
    (folder / "arm.urdf").write_text(yaw_pitch_roll_urdf(0.05))
    record = {
        "mechanism": {"urdf": "arm.urdf"},
        "workspace": {"kind": "sobol", "n": 16, "seed": 0},
        "explore": {
            "candidates": "auto",
            "default_box": 0.3,
            "max_springs": 3,
            "spring": {"type": "zero_free_length", "stiffness": {"lower": 0, "upper": 20000}},
            "approximate": 1,  # one approximate design for the count without an exact one
            "reports": False,
        },
    }
    (folder / "arm.yaml").write_text(yaml.safe_dump(record))
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        assert main(["explore", str(folder / "arm.yaml"), "--out", str(folder / "out"), "--sequential"]) == 0
    return printed.getvalue(), folder / "out"


def test_the_command_prints_the_topologies_it_faces_per_count(study):
    printed, _ = study
    # C(6, k) topologies of k springs; proven: the 4 springs (and the C(4, 2), C(4, 3) sets of them) that miss
    # the pitch or the roll
    for line in ("1 spring(s): 6 topologies, 4 proven unreachable, 2 left", "2 spring(s): 15 topologies, 6 proven"):
        assert line in printed
    assert "3 spring(s): 20 topologies, 4 proven unreachable, 16 left" in printed
    assert "screened 1 spring(s): 6 topologies, 4 proven unreachable, 2 screened without exact balance" in printed
    assert "screened 2 spring(s): 15 topologies, 6 proven unreachable, exact after screening" in printed


def test_one_spring_is_proven_or_not_found_and_two_balance_exactly(study):
    _, out = study
    screening = json.loads((out / "study.json").read_text())["screening"]
    assert sorted(screening) == ["1", "2"]  # the search stops at the first count with an exact design
    one, two = screening["1"], screening["2"]
    assert (one["unreachable"], one["screened"], one["not_found"], one["exact"]) == (4, 2, 2, [])
    assert (two["topologies"], two["unreachable"]) == (15, 6) and len(two["exact"]) == 2
    assert {"universe→link3", "link1→link3"} & set(two["exact"])  # a spring across the pitch and the roll
    rows = {row["springs"]: row for row in csv.DictReader(io.StringIO((out / "results.csv").read_text()))}
    exact = [row for row in rows.values() if row["exact"] == "True"]
    assert len(exact) == 1 and exact[0]["springs"] == " + ".join(two["exact"]) and not exact[0]["pruned"]
    assert all(row["pruned"].startswith("screened") for row in rows.values() if row is not exact[0])
    assert not (out / "best_3_springs.json").exists()  # nothing of three springs was solved


def test_the_exact_design_balances_at_random_poses_with_anchors_in_their_boxes(study):
    _, out = study
    springs = _springs(json.loads((out / "best_2_springs.json").read_text()))
    for spring in springs:
        for end in ("a", "b"):
            assert np.all(np.abs(spring[end]["point"]) <= 0.3 + 1e-9)  # the default boxes: ±0.3 m cubes
        assert 0 <= spring["k"] <= 20000
    assert _worst_torque_ratio(yaw_pitch_roll(0.05), springs) < 1e-7  # finite differences: round-off ~1e-9


def test_the_anchor_fit_finds_the_hand_derived_spring():
    # offset 0: one spring from a ground point a above the pitch joint on the yaw axis to a link-2 point b
    # along the link balances exactly when k a b = g WM (tests/spatial_helpers.py); any exact spring between
    # these boxes has its ground end on the yaw axis and its link-2 end on the link's x-y plane
    system = CoefficientSystem(yaw_pitch_roll())
    ends = [
        SpringEnds(
            "ground", ((-0.1, -0.1, H + 0.05), (0.1, 0.1, H + 0.3)), "link2", ((0.05, -0.1, -0.1), (0.4, 0.1, 0.1))
        )
    ]
    fit = fit_anchors(system, ends, (0.0, 5000.0), draws=4, seed=1)
    assert fit.relative < 1e-9
    (z_a, z_b), k = fit.anchors[0], fit.stiffness[0]
    assert abs(z_a[0]) < 1e-6 and abs(z_a[1]) < 1e-6 and abs(z_b[2]) < 1e-6
    assert k * (z_a[2] - H) * z_b[0] == pytest.approx(G * WEIGHT_MOMENT, rel=1e-6)
    again = fit_anchors(system, ends, (0.0, 5000.0), draws=4, seed=2, start=fit)  # warm: the first draw is `fit`
    assert again.draws == 1 and again.relative < 1e-9
    below = [SpringEnds("ground", ((-0.1, -0.1, H - 0.2), (0.1, 0.1, H - 0.05)), ends[0].b, ends[0].box_b)]
    # a ground end below the pitch joint (a < 0) and b > 0: the spring's sin θ₂ coefficient k a b ≤ 0 adds to
    # gravity's −g WM (its only coefficient), so the best is k = 0 and all of gravity's coefficient is left
    assert fit_anchors(system, below, (0.0, 5000.0), draws=2, seed=1).relative > 0.99


def test_the_screen_key_is_checked_and_zero_solves_every_topology(tmp_path: Path):
    (tmp_path / "arm.urdf").write_text(yaw_pitch_roll_urdf(0.05))
    record = {
        "mechanism": {"urdf": "arm.urdf"},
        "workspace": {"kind": "sobol", "n": 16, "seed": 0},
        "explore": {"candidates": "auto", "max_springs": 1, "screen": -1},
    }
    with pytest.raises(InputError, match=r"arm.yaml: explore.screen must be an integer ≥ 0"):
        Study(record, tmp_path, "arm.yaml")
    with pytest.raises(InputError, match=r"arm.yaml: solve.seeds must be distinct, got \[1, 1\]"):
        Study({**record, "solve": {"seeds": [1, 1]}}, tmp_path, "arm.yaml")
    plain = Study({**record, "explore": {**record["explore"], "screen": 0}}, tmp_path, "arm.yaml")
    assert plain.search is None and len(plain.tasks) == 6 - 4  # every topology not proven unreachable


@pytest.mark.slow
def test_the_ur5_screen_finds_three_springs_that_balance_exactly():
    # the UR5 of example-robot-data, candidates auto (span 2, collision boxes grown by 5 cm; ±0.3 m at the
    # ground): C(15, 2) = 105 and C(15, 3) = 455 topologies of two and three springs (combinatorics)
    ur5 = sb.Mechanism.from_robot("ur5")
    candidates = auto_candidates(ur5)
    test = SpatialTest(ur5, candidates)
    topologies = enumerate_topologies(len(candidates), 3)
    verdicts = {topology: found for topology in topologies if (found := test.verdict(topology))}
    search = Search(ur5, candidates, verdicts, (0.0, 5000.0), 4, 0)
    two = search.screen(2, [], topologies, False)  # count 1 left out (3 topologies, none exact: the guide)
    three = search.screen(3, [], topologies, False)  # those that complete the best pairs first
    assert (two.topologies, two.exact, two.not_found) == (105, [], 105 - two.unreachable)
    assert (three.topologies, len(three.exact)) == (455, 3) and three.screened <= three.topologies - three.unreachable
    fit, ends = search.fits[search.found[3]], search.ends(search.found[3])
    springs = [
        {
            "a": {"body": s.anchors["a"].body, "point": list(s.anchors["a"].point)},
            "b": {"body": s.anchors["b"].body, "point": list(s.anchors["b"].point)},
            "k": float(s.parameters["stiffness"]),
        }
        for s in fit.springs(ends)
    ]
    for spring, end in zip(springs, ends):
        for point, (lower, upper) in ((spring["a"]["point"], end.box_a), (spring["b"]["point"], end.box_b)):
            assert np.all(np.array(point) >= np.array(lower) - 1e-12) and np.all(
                np.array(point) <= np.array(upper) + 1e-12
            )
    assert _worst_torque_ratio(ur5, springs) < 1e-7


def test_elimination_from_every_candidate_ends_exact():
    # one spring per auto candidate (6), fitted at once, then dropped one at a time while the rest stays exact
    arm = yaw_pitch_roll(0.05)
    candidates = auto_candidates(arm, default=0.3)
    ends = [SpringEnds(c.a, c.box_a, c.b, c.box_b) for c in candidates]
    test = SpatialTest(arm, candidates)
    found = eliminate(
        CoefficientSystem(arm), ends, lambda t: test.verdict(t) is not None, ((0.0, 20000.0), 4, 0), 1e-9, False
    )
    assert found is not None
    topology, fit = found
    assert 2 <= len(topology) < len(candidates) and fit.relative < 1e-9  # 1 spring: see the first tests
    springs = [
        {
            "a": {"body": s.anchors["a"].body, "point": list(s.anchors["a"].point)},
            "b": {"body": s.anchors["b"].body, "point": list(s.anchors["b"].point)},
            "k": float(s.parameters["stiffness"]),
        }
        for s in fit.springs([ends[i] for i in topology])
    ]
    assert _worst_torque_ratio(arm, springs) < 1e-7


def test_running_the_search_again_solves_nothing_twice(study):
    _, out = study
    rows = list(csv.DictReader(io.StringIO((out / "results.csv").read_text())))
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):  # the same config into the same folder: the search resumes
        assert main(["explore", str(out.parent / "arm.yaml"), "--out", str(out), "--sequential"]) == 0
    assert f"solved 0 now, {len(rows)} from an earlier run" in printed.getvalue()
