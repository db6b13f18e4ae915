"""Honest outcomes of ``export`` and ``view`` (springbalance.cli.outcome): a design that fails a check is
not exported unless ``--partial`` is given (then every file is marked partial), and ``view`` shows it but
prints its failures and exits with 3, as ``design``, ``evaluate`` and ``report`` do.

The failing design is config_helpers.THROUGH (a spring through link1 at every pose), saved with
``design --partial``: its failures are ``partial`` and ``overlap``. The passing one balances a single link
exactly: a zero-free-length spring of stiffness k from a point at height h above the pivot to the point at
distance r along the line from the pivot to the centre of mass (at c) stores ½ k (h² + r² − 2 h r cos θ), θ the
link's angle from the vertical, against the weight's m g c cos θ: their sum is constant when k h r = m g c
(docs/model.md §9).
"""

from __future__ import annotations

import json
from pathlib import Path

import mujoco
import numpy as np
import pytest

import springbalance as sb
from cli_helpers import failure_kinds, until_ctrl_c
from config_helpers import ROOT, THROUGH, config_file
from springbalance.cli import main
from springbalance.export.urdf import sidecar_path


@pytest.fixture(scope="module")
def failing_design(tmp_path_factory) -> Path:
    """THROUGH solved and saved with ``--partial`` (it fails ``overlap``, and is marked ``partial``)."""
    folder = tmp_path_factory.mktemp("failing")
    out = folder / "design.json"
    assert main(["design", str(config_file(folder, THROUGH)), "--out", str(out), "--partial", "--quiet"]) == 3
    return out


def _balanced_link(folder: Path) -> Path:
    """A saved design that passes every check: single_link_r1.urdf balanced exactly by one zero-free-length
    spring (k h r = m g c: see the module docstring)."""
    mechanism = sb.Mechanism.from_urdf(ROOT / "urdf" / "single_link_r1.urdf")  # 8 kg, c = 0.183 m along z
    mass, lever = 8.0, np.array([0.0, 0.0, 0.183])
    gravity = float(np.linalg.norm(mechanism.gravity))
    com = float(np.linalg.norm(lever))
    height, reach = 0.2, 0.3  # [m]
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, height)),
        sb.Anchor("link1", tuple(reach * lever / com)),
        name="balancer",
        stiffness=mass * gravity * com / (height * reach),
    )
    result = sb.DesignResult(sb.DesignProblem(mechanism, sb.Workspace.grid(mechanism, 31), [spring]), np.zeros(0))
    return result.save(folder / "balanced.json")


def _export(design: Path, folder: Path, *extra: str) -> tuple[int, list[Path]]:
    urdf, mjcf = folder / "arm.urdf", folder / "arm.xml"
    code = main(["export", str(design), "--urdf", str(urdf), "--mjcf", str(mjcf), *extra])
    return code, [urdf, sidecar_path(urdf), mjcf]


def test_export_of_a_failing_design_writes_nothing_and_exits_3(failing_design, tmp_path, capsys):
    capsys.readouterr()
    (tmp_path / "arm.xml").write_text("keep me")
    code, files = _export(failing_design, tmp_path)
    captured = capsys.readouterr()
    assert code == 3
    assert not files[0].exists() and not files[1].exists() and files[2].read_text() == "keep me"
    assert not list(tmp_path.glob(".arm*"))  # no temporary file left either
    assert failure_kinds(captured.err) == ["partial", "overlap"]
    assert "nothing written" in captured.err.splitlines()[-1] and "--partial" in captured.err.splitlines()[-1]
    assert "wrote" not in captured.out


def test_export_partial_writes_every_file_marked_and_exits_3(failing_design, tmp_path, capsys):
    capsys.readouterr()
    code, (urdf, sidecar, mjcf) = _export(failing_design, tmp_path, "--partial")
    captured = capsys.readouterr()
    assert code == 3
    assert "wrote" in captured.out and "partial" in captured.out
    assert failure_kinds(captured.err) == ["partial", "overlap"]
    # every file says so, and still loads where it is meant to be read
    for path in (urdf, mjcf):  # a comment before the root element (after the XML declaration, if any)
        head = path.read_text().split("<robot" if path == urdf else "<mujoco", 1)[0]
        assert "<!-- springbalance: PARTIAL design, not to be built" in head and "overlap" in head
    record = json.loads(sidecar.read_text())
    assert record["partial"] is True and "overlap" in record["partial_reason"]
    assert [spring["name"] for spring in record["springs"]] == ["through"]
    assert sb.Mechanism.from_urdf(urdf).nv == 2
    mujoco.MjModel.from_xml_path(str(mjcf))


def test_export_of_a_design_that_passes_exits_0_unmarked(tmp_path, capsys):
    code, (urdf, sidecar, mjcf) = _export(_balanced_link(tmp_path), tmp_path)
    captured = capsys.readouterr()
    assert code == 0 and "springbalance: failure" not in captured.err
    assert "PARTIAL" not in urdf.read_text() and "PARTIAL" not in mjcf.read_text()
    assert "partial" not in json.loads(sidecar.read_text())


def test_view_of_a_failing_design_prints_its_failures_and_exits_3_when_stopped(failing_design):
    code, out, err = until_ctrl_c(["view", str(failing_design), "--frames", "2"])
    assert code == 3, (code, err)
    assert "Traceback" not in err and "stopped" in out
    assert failure_kinds(err) == ["partial", "overlap"]
    assert "shown all the same" in err
