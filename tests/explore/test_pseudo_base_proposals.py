"""``explore`` proposes pseudo-bases when springs alone found no exact design (issue 29, part 2).

Expected values by hand from the URDFs:

- KR-like arm (urdf/kr_like_6r.urdf): a1 turns about the vertical, so gravity does not load it; a2…a6 are loaded.
  Gravity is along z and a1 leads, so every pseudo-base keeps only the vertical and skips a1. Its parallelograms
  span the links from a2 on: a2→a3 0.6 m, a3→a4 0.2 m, a4→a5 0.45 m, a5→a6 0.1 m, each with two 0.05 m cranks, at
  0.3 kg/m: pb_a2 0 kg (no parallelogram), pb_a3 0.3·0.7, pb_a4 0.3·1.0, pb_a5 0.3·1.55, pb_a6 0.3·1.75 kg.
- Gravity tilted off z loads a1 too and needs the full orientation: pb_a1 sits on the base (0 kg), pb_a2's
  parallelogram spans a1→a2, |(0.15, 0, 0.2)| = 0.25 m: 0.3·(0.25 + 0.1) kg.
- Seed 004 (docs/model.md §1.1): a spring from each pseudo-base to its link, with those beyond it, balances
  exactly: every proposal says so.
- Two-link arm (urdf/two_link_planar.urdf): one spring from the ground to link1 cannot hold the elbow, so the study
  ends without an exact design. pb_elbow weighs 0.3·(0.5 + 0.1) = 0.18 kg at the elbow, 0.5 m out: it adds
  0.18 g 0.5 |cos θ₁| on the shoulder (peak at θ₁ = 0 within ±90°) and nothing on the elbow.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import springbalance as sb
from config_helpers import config_file
from springbalance.cli import main
from springbalance.explore.pseudo_base_proposals import _exact, propose_pseudo_bases

ROOT = Path(__file__).resolve().parents[2]
KR = ROOT / "urdf" / "kr_like_6r.urdf"
TWO_LINK = ROOT / "urdf" / "two_link_planar.urdf"
G = 9.81


def test_kr_arm_gets_vertical_pseudo_bases_on_the_loaded_joints_lightest_first():
    proposals = propose_pseudo_bases(sb.Mechanism.from_urdf(KR))
    assert [p["joint"] for p in proposals] == ["a2", "a3", "a4", "a5", "a6"]
    expected = [0.0, 0.3 * 0.7, 0.3 * 1.0, 0.3 * 1.55, 0.3 * 1.75]
    assert [p["mass"] for p in proposals] == pytest.approx(expected, abs=1e-12)
    assert {p["keep"] for p in proposals} == {"vertical"} and {p["mass_from"] for p in proposals} == {"estimate"}
    assert [p["link"] for p in proposals] == ["link2", "link3", "link4", "link5", "link6"]
    assert all(p["exact"] is True and p["residual"] <= 1e-9 for p in proposals)
    assert proposals[2]["with"] == ["a5", "a6"]
    assert max(proposals[0]["peak_torque"].values()) == 0.0  # massless: adds nothing


def test_config_masses_rank_and_tilted_gravity_needs_the_orientation():
    given = sb.Mechanism.from_urdf(KR, pseudo_bases=[{"joint": "a3", "mass": 2.0, "com": [0, 0, 0.1]}])
    proposals = propose_pseudo_bases(given)
    assert [p["joint"] for p in proposals] == ["a2", "a4", "a5", "a6", "a3"]  # the config's 2 kg ranks last
    assert proposals[-1]["mass"] == 2.0 and proposals[-1]["mass_from"] == "config"
    tilted = propose_pseudo_bases(sb.Mechanism.from_urdf(KR, gravity=[3.0, 0.0, -9.0]))
    by_joint = {p["joint"]: p for p in tilted}
    assert sorted(by_joint) == ["a1", "a2", "a3", "a4", "a5", "a6"]
    assert {p["keep"] for p in tilted} == {"orientation"}
    assert by_joint["a1"]["mass"] == 0.0
    assert by_joint["a2"]["mass"] == pytest.approx(0.3 * 0.35, abs=1e-12)
    assert all(p["exact"] for p in tilted)


def test_a_study_without_an_exact_design_lists_the_proposals(tmp_path, capsys):
    record = {
        "mechanism": {"urdf": str(TWO_LINK)},
        "workspace": {"kind": "sobol", "n": 32},
        "explore": {
            "candidates": [
                {
                    "a": {"body": "universe", "box": {"lower": [0, 0, 0.2], "upper": [0, 0, 0.2]}},
                    "b": {"body": "link1", "box": {"lower": [0.3, 0, 0], "upper": [0.3, 0, 0]}},
                }
            ],
            "max_springs": 1,
            "prune": False,
            "starts": 1,
            "spring": {"type": "zero_free_length", "stiffness": {"lower": 0, "upper": 1000}},
            "reports": False,
        },
    }
    out = tmp_path / "study"
    assert main(["explore", str(config_file(tmp_path, record, "study.yaml")), "--out", str(out), "--sequential"]) == 0
    printed = capsys.readouterr().out
    saved = json.loads((out / "study.json").read_text())["pseudo_base_proposals"]
    elbow = next(p for p in saved if p["joint"] == "elbow")
    assert elbow["mass"] == pytest.approx(0.18, abs=1e-12) and elbow["exact"] is True
    peak = 0.18 * G * 0.5
    assert (
        elbow["peak_torque"]["shoulder"] == pytest.approx(peak, rel=1e-3) and elbow["peak_torque"]["shoulder"] <= peak
    )
    assert elbow["peak_torque"]["elbow"] == pytest.approx(0.0, abs=1e-12)
    assert "No exact design with springs alone." in printed
    assert "pb_elbow at elbow (keeps orientation): 0.18 kg (estimate), weight adds shoulder 0.88" in printed
    page = (out / "report.html").read_text()
    assert '<h2 id="pseudo-bases">Pseudo-bases</h2>' in page and "pb_elbow → link2: exact" in page


def test_joints_beyond_a_slider_get_no_pseudo_base_and_say_why():
    """With a2 prismatic, a parallelogram cannot carry the orientation past it (docs/model.md §1.1): a3…a6 are
    listed last without a mass; a1 and a2 get theirs, untested (the exact test takes revolute joints)."""
    text = KR.read_text().replace('<joint name="a2" type="revolute">', '<joint name="a2" type="prismatic">')
    proposals = propose_pseudo_bases(sb.Mechanism.from_urdf_string(text))
    assert [p["joint"] for p in proposals[-4:]] == ["a3", "a4", "a5", "a6"]
    assert all(p["mass"] is None and "lies beyond the prismatic joint 'a2'" in p["note"] for p in proposals[-4:])
    assert all(p["exact"] is None and "prismatic" in p["note"] for p in proposals[:2])


def test_the_exact_verdict_needs_the_pseudo_bases_beyond():
    """pb_a3 alone cannot balance links 3…6: the weights of links 4…6 make terms in a4…a6 that no spring from pb_a3
    to link3 reaches; with pseudo-bases at a4…a6 too, every term of a3's subtree goes (seed 004)."""
    bare = sb.Mechanism.from_urdf(KR)
    source = {**bare.source, "gravity": [0.0, 0.0, -G]}
    links = {f"a{i}": f"link{i}" for i in range(1, 7)}
    alone, residual, _ = _exact(source, bare, [{"joint": "a3", "keep": "vertical"}], links, "a3")
    assert alone is False and residual > 1e-3
    beyond = [{"joint": f"a{i}", "keep": "vertical"} for i in range(3, 7)]
    together, residual, _ = _exact(source, bare, beyond, links, "a3")
    assert together is True and residual <= 1e-9
