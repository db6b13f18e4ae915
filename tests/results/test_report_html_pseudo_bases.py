"""report.html's "Pseudo-bases" section (issue 29): each pseudo-base, its joint, what it keeps, its mass and the
torque its weight adds before balancing; no section for a design without pseudo-bases.

Expected numbers by hand: urdf/two_link_planar.urdf has link1 0.5 m long (2 kg at 0.25 m) and link2 1 kg at 0.2 m
with a 0.5 kg tool at 0.4 m, both joints about horizontal axes. A 0.25 kg pseudo-base at the elbow weighs at the
elbow, so it adds ``0.25 g 0.5 |cos θ₁|`` on the shoulder (peak 1.226 N·m at θ₁ = 0) and nothing on the elbow. The
arm's shoulder peak, at the stretched horizontal pose, is ``(2·0.25 + 1.75·0.5 + 0.4) g = 1.775 g``, so the
pseudo-base's share is 0.125/1.775 = 7.04 %.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import springbalance as sb
from springbalance.design.problem import DesignProblem
from springbalance.results.html_report import report_html
from springbalance.results.result import DesignResult

ROOT = Path(__file__).resolve().parents[2]
TWO_LINK = ROOT / "urdf" / "two_link_planar.urdf"
G = 9.81


def _design(pseudo_bases):
    mechanism = sb.Mechanism.from_urdf(TWO_LINK, pseudo_bases=pseudo_bases)
    body = "pb_elbow" if pseudo_bases else "link1"
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor(body, [0, 0, 0.2]), sb.Anchor("link2", [0.1, 0, 0]), "s", stiffness=196.2
    )
    poses = np.array([[0.0, 0.0], [0.6, -0.3], [1.2, 0.9], [-0.8, 1.5]])  # the first: stretched out, horizontal
    return DesignResult(DesignProblem(mechanism, sb.Workspace.from_array(mechanism, poses), [spring]), np.zeros(0))


def _page(result):
    return report_html(result, scene=None, torques=None, histogram=None)


def test_report_html_shows_each_pseudo_base_and_the_torque_its_weight_adds():
    page = _page(_design([{"joint": "elbow", "mass": 0.25, "com": [0, 0, 0.01], "keep": "vertical"}]))
    assert '<h2 id="pseudo-bases">Pseudo-bases</h2>' in page
    section = page.split('<h2 id="pseudo-bases">', 1)[1].split("<h2", 1)[0]
    peak = 0.25 * G * 0.5
    share = 100 * 0.125 / 1.775
    assert "0.25 kg in all" in section
    assert f"shoulder {peak:.4g} N·m ({share:.3g} %)" in section
    assert "elbow 0" not in section  # the pseudo-base sits at the elbow: no lever on it
    row = section.split("<tr><td class=l>pb_elbow</td>", 1)[1].split("</tr>", 1)[0]
    assert "<td class=l>elbow</td><td class=l>vertical</td><td>0.25</td><td>(0, 0, 0.01)</td>" in row
    assert f"shoulder {peak:.4g} N·m</td>" in row


def test_report_html_has_no_pseudo_base_section_without_pseudo_bases():
    assert 'id="pseudo-bases"' not in _page(_design([]))
