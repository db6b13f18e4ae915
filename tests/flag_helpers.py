"""Checks shared by the tests of a design's findings (springbalance.results.flags): a flag is in every
report (text, report.html, design.json) under the heading of its severity, or a design has none."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

import springbalance as sb
from springbalance.springs.laws.helical_extension import HelicalExtensionSpring

#: a horizontal slide (0.1 … 0.3 m) carrying a pendulum (−90° … 90°): gravity (along −z) never loads the slide
SLIDER_URDF = """<?xml version="1.0"?>
<robot name="slider_pendulum">
  <link name="base"/>
  <link name="cart">
    <inertial><origin xyz="0 0 0"/><mass value="1.0"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="arm">
    <inertial><origin xyz="0.25 0 0"/><mass value="2.0"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.04" iyz="0" izz="0.04"/></inertial>
  </link>
  <joint name="slide" type="prismatic">
    <parent link="base"/><child link="cart"/><axis xyz="1 0 0"/>
    <limit lower="0.1" upper="0.3" effort="100" velocity="1"/>
  </joint>
  <joint name="pitch" type="revolute">
    <parent link="cart"/><child link="arm"/><axis xyz="0 -1 0"/>
    <limit lower="-1.5707963267948966" upper="1.5707963267948966" effort="100" velocity="1"/>
  </joint>
</robot>
"""


def html_rows(path: Path, severity: str = "warning") -> list[tuple[str, str]]:
    """(kind, row text) of every row of the report's Warnings table (``severity="failure"``: of its
    Failures table)."""
    page = path.read_text()
    rows = re.findall(rf'<tr class="{severity} ([a-z_]+)">(.*?)</tr>', page, flags=re.S)
    return [(kind, re.sub(r"<[^>]+>", " ", text)) for kind, text in rows]


def assert_flagged(result, tmp_path: Path, kind: str, subject: str, severity: str = "warning") -> dict:
    """The flag (kind, subject) of ``severity`` is in result.warnings(), the text report, report.html and
    design.json (a failure also in result.failures() and design.json's "failures"); returns its saved record."""
    found = [flag for flag in result.warnings() if flag.kind == kind and flag.subject == subject]
    assert len(found) >= 1, [str(flag) for flag in result.warnings()]
    flag = found[0]
    assert flag.message and flag.hint
    assert flag.severity == severity
    assert (flag in result.failures()) == (severity == "failure")
    assert result.ok == (not result.failures())

    # (a) the text report: a Failures or Warnings section after the tables, the flag with its hint;
    # the failures come before the warnings
    heading = "\nFailures (" if severity == "failure" else "\nWarnings ("
    table = result.table()
    section = table[table.index(heading) :]
    if severity == "failure":
        section = section[: section.index("\nWarnings")]
    assert table.index("Actuator torque") < table.index(heading)
    assert f"[{kind}] {flag.message}" in section
    assert f"hint: {flag.hint}" in section

    # (b) report.html: the failures' table before the warnings'
    page = result.report(tmp_path / "report", scene=False)
    assert page.name == "report.html"
    text = page.read_text()
    assert 'id="warnings"' in text
    if severity == "failure":
        assert text.index('id="failures"') < text.index('id="warnings"')
    rows = [text for row_kind, text in html_rows(page, severity) if row_kind == kind]
    assert any(subject in text for text in rows), rows

    # (c) design.json: top-level "warnings" (every finding), "failures" (the failures), records
    # {kind, severity, subject, message, hint?}
    saved = json.loads(result.save(tmp_path / "design.json").read_text())
    records = [record for record in saved["warnings"] if record["kind"] == kind and record["subject"] == subject]
    assert records
    assert set(records[0]) <= {"kind", "severity", "subject", "message", "hint"}
    assert records[0]["message"] == flag.message and records[0]["hint"] == flag.hint
    assert records[0]["severity"] == severity
    assert (records[0] in saved["failures"]) == (severity == "failure")
    assert saved["failures"] == [record for record in saved["warnings"] if record["severity"] == "failure"]
    # a saved design with warnings still loads, and reports the same warnings
    loaded = sb.DesignResult.load(tmp_path / "design.json")
    assert [f.to_dict() for f in loaded.warnings()] == saved["warnings"]
    return records[0]


def assert_clean(result, tmp_path: Path) -> None:
    """No warnings at all: "Warnings: none" in the text, the HTML, and an empty list in design.json."""
    assert result.warnings() == [], [str(flag) for flag in result.warnings()]
    assert result.table().rstrip().endswith("Warnings: none")
    page = result.report(tmp_path / "report", scene=False).read_text()
    assert 'id="warnings"' in page and "Warnings: none" in page
    assert html_rows(tmp_path / "report" / "report.html") == []
    saved = json.loads(result.save(tmp_path / "design.json").read_text())
    assert saved["warnings"] == [] and saved["failures"] == []
    assert result.ok


def fixed_design(mechanism: sb.Mechanism, springs: list, poses: np.ndarray) -> sb.DesignResult:
    """A finished design with fixed springs (no free variable) on the poses ``poses`` (N×nv) [rad]."""
    workspace = sb.Workspace.from_array(mechanism, poses)
    return sb.DesignResult(sb.DesignProblem(mechanism, workspace, springs), np.zeros(0))


def overloaded_coil() -> HelicalExtensionSpring:
    """A fixed coil on single_link_r1.urdf stretched far beyond its allowable load: 1 mm wire, D = 8 mm,
    10 coils: k = 81e9 · 1e-12 / (8 · 5.12e-7 · 10) ≈ 1978 N/m, free length 25 mm, stretched to about
    0.43 m: ≈ 800 N on a wire whose body allows 45 % · 2211 MPa ≈ 1 GPa at ≈ 20 N."""
    return HelicalExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.16]),
        sb.Anchor("link1", [0, 0, 0.3]),
        "thin",
        wire_diameter=1e-3,
        mean_diameter=8e-3,
        active_coils=10.0,
        initial_tension=5.0,
    )


def slider_pull(tmp_path: Path, weights: dict | None = None) -> sb.DesignResult:
    """The slider of :data:`SLIDER_URDF` with a zero-free-length spring from the origin to the cart: it pulls
    the slide back with k·q [N], from 0 to 100 N/m × 0.3 m = 30 N, a joint that gravity never loads; the
    pendulum's joint is untouched (5×5 grid)."""
    path = tmp_path / "slider.urdf"
    path.write_text(SLIDER_URDF)
    mechanism = sb.Mechanism.from_urdf(path)
    workspace = sb.Workspace.grid(mechanism, 5)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0)), sb.Anchor("cart", (0, 0, 0)), name="pull", stiffness=100.0
    )
    return sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring], weights=weights), np.zeros(0))
