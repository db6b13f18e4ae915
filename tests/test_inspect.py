"""``springbalance inspect``: bodies, joints, masses and ground of a robot or URDF; robot-name suggestions.

The expected numbers are read from the URDF files themselves (``xml.etree``), not from
springbalance's own output.
"""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

import springbalance as sb
from springbalance.cli import main
from springbalance.model import robots

ROOT = Path(__file__).resolve().parents[1]
TWO_LINK = ROOT / "urdf" / "two_link_planar.urdf"
PARALLELOGRAM = ROOT / "urdf" / "parallelogram_arm.urdf"


# ---------------------------------------------------------------------- the URDF, read independently
def urdf_links(path: Path) -> dict[str, tuple[float, list[float]]]:
    """Link name → (mass [kg], centre of mass ``<inertial><origin xyz>`` [m]); a link without inertia weighs 0."""
    links = {}
    for link in ElementTree.parse(path).getroot().findall("link"):
        mass = link.find("inertial/mass")
        origin = link.find("inertial/origin")
        xyz = origin.get("xyz", "0 0 0") if origin is not None else "0 0 0"
        links[link.get("name")] = (
            float(mass.get("value")) if mass is not None else 0.0,
            [float(value) for value in xyz.split()],
        )
    return links


def urdf_joints(path: Path) -> dict[str, dict]:
    """Joint name → type, parent, child, axis, limits and mimic element, as written in the URDF."""
    joints = {}
    for joint in ElementTree.parse(path).getroot().findall("joint"):
        axis, limit, mimic = joint.find("axis"), joint.find("limit"), joint.find("mimic")
        joints[joint.get("name")] = {
            "type": joint.get("type"),
            "parent": joint.find("parent").get("link"),
            "child": joint.find("child").get("link"),
            "axis": [float(value) for value in (axis.get("xyz") if axis is not None else "1 0 0").split()],
            "lower": float(limit.get("lower")) if limit is not None and limit.get("lower") else None,
            "upper": float(limit.get("upper")) if limit is not None and limit.get("upper") else None,
            "mimic": None
            if mimic is None
            else {
                "joint": mimic.get("joint"),
                "multiplier": float(mimic.get("multiplier", "1")),
                "offset": float(mimic.get("offset", "0")),
            },
        }
    return joints


def urdf_ground(path: Path) -> set[str]:
    """``universe``, the root link and every link welded to it by a chain of fixed joints."""
    joints = urdf_joints(path)
    children = {joint["child"] for joint in joints.values()}
    ground = {name for name in urdf_links(path) if name not in children}  # the root link
    grown = True
    while grown:
        welded = {joint["child"] for joint in joints.values() if joint["type"] == "fixed" and joint["parent"] in ground}
        grown = not welded <= ground
        ground |= welded
    return ground | {"universe"}


def run(capsys, argv: list[str]) -> str:
    """Run ``main(argv)``, expect exit 0 and nothing on stderr; return stdout."""
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    return captured.out


def run_json(capsys, argv: list[str]) -> dict:
    return json.loads(run(capsys, ["inspect", *argv, "--json"]), parse_constant=_no_constants)


def _no_constants(name: str):
    raise AssertionError(f"inspect --json printed {name}, which is not JSON")


def run_error(capsys, argv: list[str]) -> str:
    """Run ``main(argv)``, expect exit 2 and one error line on stderr, nothing on stdout; return that line."""
    assert main(argv) == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("springbalance: error: ")
    assert "Traceback" not in captured.err
    assert captured.out == ""
    return lines[0]


# ---------------------------------------------------------------------- two_link_planar.urdf
def test_json_of_two_link_planar_matches_the_urdf(capsys):
    summary = run_json(capsys, [str(TWO_LINK)])
    links, joints = urdf_links(TWO_LINK), urdf_joints(TWO_LINK)

    bodies = {body["name"]: body for body in summary["bodies"]}
    assert list(bodies) == ["universe", "base", "link1", "link2", "tool"]
    assert set(bodies) == set(links) | {"universe"}
    for name, (mass, com) in links.items():
        assert bodies[name]["mass"] == pytest.approx(mass, abs=1e-12)
        assert bodies[name]["com"] == pytest.approx(com, abs=1e-12)
    # the numbers of the URDF's own comment: link1 2.0 kg at 0.25 m, link2 1.0 kg at 0.20 m, tool 0.5 kg
    assert (bodies["link1"]["mass"], bodies["link2"]["mass"], bodies["tool"]["mass"]) == (2.0, 1.0, 0.5)
    assert summary["total_mass"] == pytest.approx(sum(mass for mass, _ in links.values())) == pytest.approx(3.5)
    assert summary["moving_mass"] == pytest.approx(3.5)

    parent_joint = {joint["child"]: name for name, joint in joints.items()}
    for name, body in bodies.items():
        assert body["parent_joint"] == parent_joint.get(name)
    assert bodies["tool"]["moved_by"] == "elbow"  # welded to link2 by the fixed joint tool_mount
    assert summary["ground"] == ["universe", "base"]
    assert set(summary["ground"]) == urdf_ground(TWO_LINK)
    assert [name for name, body in bodies.items() if body["ground"]] == summary["ground"]

    assert [joint["name"] for joint in summary["joints"]] == list(joints) == ["shoulder", "elbow", "tool_mount"]
    for record in summary["joints"]:
        expected = joints[record["name"]]
        assert (record["type"], record["parent"], record["child"]) == (
            expected["type"],
            expected["parent"],
            expected["child"],
        )
        if expected["type"] == "fixed":
            assert record["axis"] is None and record["lower"] is None and record["upper"] is None
            assert record["dof"] is False
        else:
            assert record["axis"] == pytest.approx(expected["axis"])
            assert record["lower"] == pytest.approx(expected["lower"], abs=1e-15)
            assert record["upper"] == pytest.approx(expected["upper"], abs=1e-15)
            assert record["unit"] == "rad" and record["dof"] is True
        assert record["mimic"] is None
    assert math.degrees(summary["joints"][1]["upper"]) == pytest.approx(150.0)
    assert summary["dofs"] == 2
    assert summary["gravity"] == [0.0, 0.0, -9.81]


def test_text_of_two_link_planar(capsys):
    text = run(capsys, ["inspect", str(TWO_LINK)])
    links, joints = urdf_links(TWO_LINK), urdf_joints(TWO_LINK)
    lines = text.splitlines()
    assert lines[0].startswith("two_link_planar (URDF ")
    assert "  2 degrees of freedom: shoulder, elbow" in lines
    assert f"  total mass {sum(mass for mass, _ in links.values()):g} kg, of which 3.5 kg moves" in lines
    assert "  ground (cannot move): universe, base" in lines

    rows = {line.split()[0]: line.split(None, 2) for line in lines if line.startswith("  ")}
    for name, (mass, com) in links.items():
        assert float(rows[name][1]) == pytest.approx(mass)
        numbers = re.match(r"\(([^)]*)\)", rows[name][2]).group(1)
        assert [float(value) for value in numbers.split(",")] == pytest.approx(com)
    for name in ("shoulder", "elbow"):
        line = next(line for line in lines if line.startswith(f"  {name} "))
        lower, upper = (round(math.degrees(joints[name][end])) for end in ("lower", "upper"))
        assert f"({lower}° … {upper}°)" in line  # the URDF limits in degrees: ±90° and ±150°
        assert f"{joints[name]['parent']} → {joints[name]['child']}" in line
        assert "revolute" in line and "(0, -1, 0)" in line
    assert "(-90° … 90°)" in text and "(-150° … 150°)" in text
    tool_mount = next(line for line in lines if line.startswith("  tool_mount "))
    assert tool_mount.split()[1] == "fixed" and "link2 → tool" in tool_mount


def test_summary_is_plain_json_data():
    summary = sb.Mechanism.from_urdf(TWO_LINK).summary()
    assert json.loads(json.dumps(summary)) == summary


# ---------------------------------------------------------------------- a robot by name
def test_ur5_by_name_total_mass_is_the_sum_of_the_urdf_link_masses(capsys):
    path = robots.robot_urdf("ur5")
    links, joints = urdf_links(path), urdf_joints(path)
    summary = run_json(capsys, ["ur5"])
    assert summary["source"]["kind"] == "robot" and summary["source"]["robot"] == "ur5"
    total = sum(mass for mass, _ in links.values())
    assert total == pytest.approx(20.9939)  # ur5_robot.urdf: base_link 4 kg ... wrist_3_link 0.1879 kg
    assert summary["total_mass"] == pytest.approx(total, abs=1e-9)
    ground = urdf_ground(path)
    assert set(summary["ground"]) == ground
    assert summary["moving_mass"] == pytest.approx(total - sum(links[name][0] for name in ground - {"universe"}))
    bodies = {body["name"]: body for body in summary["bodies"]}
    for name, (mass, com) in links.items():
        assert bodies[name]["mass"] == pytest.approx(mass, abs=1e-9)
        if mass > 0:
            assert bodies[name]["com"] == pytest.approx(com, abs=1e-9)
    assert {joint["name"] for joint in summary["joints"]} == set(joints)
    for record in summary["joints"]:
        expected = joints[record["name"]]
        assert record["type"] == expected["type"]
        if expected["type"] == "revolute":
            assert (record["lower"], record["upper"]) == pytest.approx((expected["lower"], expected["upper"]))
            assert record["axis"] == pytest.approx(expected["axis"])
    assert summary["dofs"] == 6

    text = run(capsys, ["inspect", "ur5"])
    assert f"total mass {total:g} kg" in text
    assert "shoulder_lift_joint" in text and "upper_arm_link" in text


def test_mimic_joints_with_and_without_mimic(capsys):
    joints = urdf_joints(PARALLELOGRAM)
    summary = run_json(capsys, [str(PARALLELOGRAM), "--mimic"])
    records = {joint["name"]: joint for joint in summary["joints"]}
    for name, expected in joints.items():
        assert records[name]["mimic"] == expected["mimic"]
        assert records[name]["dof"] is (expected["mimic"] is None and expected["type"] != "fixed")
    assert summary["dofs"] == 2
    text = run(capsys, ["inspect", str(PARALLELOGRAM), "--mimic"])
    assert "mimic: -1 × elbow + 0" in text

    # without --mimic they are independent joints, and a one-line warning says how to couple them
    assert main(["inspect", str(PARALLELOGRAM), "--json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["dofs"] == 4
    (warning,) = captured.err.splitlines()
    assert warning.startswith("springbalance: warning: ") and "--mimic" in warning


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize("robot, suggestion", [("ur55", "'ur5'"), ("pnda", "'panda'"), ("UR5", "'ur5'")])
def test_misspelled_robot_gets_a_suggestion(capsys, robot, suggestion):
    line = run_error(capsys, ["inspect", robot])
    assert f"unknown example-robot-data robot {robot!r}; did you mean {suggestion}" in line
    assert "springbalance robots" in line
    assert "double_pendulum" not in line and "talos" not in line  # not the whole list of ~75 names


def test_suggestions_are_at_most_three_and_absent_when_nothing_is_close():
    with pytest.raises(sb.InputError) as caught:
        robots.robot_urdf("double_pendulm")
    suggested = re.search(r"did you mean (.*)\?", str(caught.value)).group(1)
    assert suggested.count("'") == 6  # three quoted names
    with pytest.raises(sb.InputError) as caught:
        robots.robot_urdf("zzzzzz")
    assert "did you mean" not in str(caught.value) and "`springbalance robots`" in str(caught.value)


def test_bad_paths_exit_2_with_one_line(tmp_path, capsys):
    assert "does not exist" in run_error(capsys, ["inspect", str(tmp_path / "absent.urdf")])
    assert "does not exist" in run_error(capsys, ["inspect", "no/such/arm"])
    malformed = tmp_path / "malformed.urdf"
    malformed.write_text("<robot name='x'><link name='a'><joint")
    assert "could not be parsed" in run_error(capsys, ["inspect", str(malformed)])
    assert "is a directory" in run_error(capsys, ["inspect", str(tmp_path)])


@pytest.mark.parametrize(
    "argv, expected",
    [
        (["inspect", "pnda"], "did you mean 'panda'?"),
        (["inspect", "urdf/absent.urdf"], "URDF file 'urdf/absent.urdf' does not exist"),
    ],
)
def test_python_m_errors_are_one_line_without_traceback(argv, expected):
    completed = subprocess.run(
        [sys.executable, "-m", "springbalance", *argv], capture_output=True, text=True, cwd=ROOT, timeout=120
    )
    assert completed.returncode == 2
    assert completed.stdout == ""
    lines = completed.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("springbalance: error: "), completed.stderr
    assert expected in lines[0]
    assert "Traceback" not in completed.stderr


def test_python_m_version():
    completed = subprocess.run(
        [sys.executable, "-m", "springbalance", "--version"], capture_output=True, text=True, timeout=120
    )
    assert completed.returncode == 0, completed.stderr
    assert completed.stdout == f"springbalance {sb.__version__}\n"
