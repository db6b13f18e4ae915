"""The order a spring maker can quote (springbalance.results.order, ``springbalance order``).

The demo's loads are recomputed here from the saved geometry with Pinocchio alone: each anchor's world
position at every workspace pose, the spring's length, and the helical extension law of Shigley ch. 10
(music wire G = 81.0 GPa, Table 10-5): ``k = G d⁴/(8 D³ n)``, ``L0 = d (n + 1) + 2 (D − d)``,
``F = F0 + k (L − L0)``. The wire tolerance is ASTM A228's (±0.0005 in over 0.063-0.080 in, ±0.001 in over
0.080-0.250 in); the load tolerance EN 15800's ``A_F = (α_F k_F + 1.5 F/100) Q`` evaluated here.
"""

from __future__ import annotations

import csv
import json
import xml.etree.ElementTree as ElementTree
from importlib import resources
from pathlib import Path

import jsonschema
import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from flag_helpers import overloaded_coil
from physics_helpers import ReferencePotential, RefSpring
from springbalance.cli import main
from springbalance.results.order import OrderOptions, order_files, spring_orders
from springbalance.results.order.schema import ORDER_SCHEMA
from springbalance.springs import spring_from_dict
from springbalance.springs.laws.helical_compression import HelicalCompressionSpring

ROOT = Path(__file__).resolve().parents[2]
URDF = ROOT / "urdf"
G_MUSIC = 81.0e9  # [Pa] Shigley Table 10-5
INCH = 25.4e-3  # [m]
SVG = "{http://www.w3.org/2000/svg}"


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    """`make demo`'s design (examples/two_link.yaml), saved, and its order written by the command line."""
    folder = tmp_path_factory.mktemp("order")
    design = folder / "design.json"
    assert main(["design", str(ROOT / "examples" / "two_link.yaml"), "--out", str(design), "--quiet"]) == 0
    assert main(["order", str(design), "--out", str(folder / "order")]) == 0
    return design, folder / "order"


def _fields(spring: dict) -> dict[str, dict]:
    return {field["key"]: field for field in spring["fields"]}


def _reference_loads(record: dict, entry: dict) -> tuple[float, float, float, float]:
    """(L1, F1, L2, F2) of a saved extension coil, from Pinocchio and Shigley's law."""
    model = pin.buildModelFromUrdf(str(URDF / "two_link_planar.urdf"))
    d, D, n, initial = (entry[key] for key in ("wire_diameter", "mean_diameter", "active_coils", "initial_tension"))
    reference = ReferencePotential(
        model,
        [
            RefSpring(
                entry["a"]["body"], tuple(entry["a"]["point"]), entry["b"]["body"], tuple(entry["b"]["point"]), 0.0
            )
        ],
    )
    lengths = np.array([reference.lengths(np.asarray(q))[0] for q in record["workspace"]["joint_values"]])
    rate, free = G_MUSIC * d**4 / (8 * D**3 * n), d * (n + 1) + 2 * (D - d)
    shortest, longest = lengths.min(), lengths.max()
    return shortest, initial + rate * (shortest - free), longest, initial + rate * (longest - free)


def _force_tolerance(d: float, D: float, n: float, force: float, q: float = 1.0) -> float:
    """EN 15800 §4 A_F [N] (d, D in m): (α_F k_F + 1.5 F/100) Q."""
    d_mm, D_mm = d * 1e3, D * 1e3
    x = min(max(D_mm / d_mm, 4), 20) / 10
    alpha = 65.92 * d_mm**3.3 / D_mm**1.6 * (-0.84 * x**3 + 3.781 * x**2 - 4.244 * x + 2.274)
    return (alpha * (1 / (3 * n * n) + 8 / (5 * n) + 0.803) + 0.015 * force) * q


@pytest.mark.slow  # the demo's design: ~10 s
def test_demo_form_has_the_loads_at_the_working_extremes(demo):
    design, folder = demo
    record = json.loads(design.read_text())
    order = json.loads((folder / "order.json").read_text())
    assert [spring["name"] for spring in order["springs"]] == [entry["name"] for entry in record["design"]]
    for entry, spring in zip(record["design"], order["springs"]):
        fields = _fields(spring)
        l1, f1, l2, f2 = _reference_loads(record, entry)
        assert fields["length_1"]["value"] == pytest.approx(l1, rel=1e-9)
        assert fields["length_2"]["value"] == pytest.approx(l2, rel=1e-9)
        assert fields["load_1"]["value"] == pytest.approx(f1, rel=1e-7)
        assert fields["load_2"]["value"] == pytest.approx(f2, rel=1e-7)
        assert f1 < f2 and spring["form"] == "DIN 2099-2 (form B)"
        d, D, n = entry["wire_diameter"], entry["mean_diameter"], entry["active_coils"]
        assert fields["load_2"]["tolerance"] == pytest.approx(_force_tolerance(d, D, n, f2), rel=1e-9)
        assert fields["free_length"]["value"] == pytest.approx(d * (n + 1) + 2 * (D - d), rel=1e-12)
        assert fields["free_length"]["reference"] and fields["free_length"]["tolerance"] is None
        assert fields["initial_tension"]["value"] == pytest.approx(entry["initial_tension"], rel=1e-12)
        # ASTM A228: 2 mm = 0.0787 in → ±0.0005 in; 3 and 5 mm (0.118, 0.197 in) → ±0.001 in
        expected = 0.0005 * INCH if d <= 0.080 * INCH else 0.001 * INCH
        assert fields["wire_diameter"]["tolerance"] == pytest.approx(expected, rel=1e-12)
        assert fields["material_standard"]["value"] == "ASTM A228/A228M"
        assert fields["controlled_diameter"]["value"] == "outer (De)"
        assert fields["outer_diameter"]["value"] == pytest.approx(D + d, rel=1e-12)
        assert fields["active_coils"]["reference"] and fields["total_coils"]["reference"]
        assert fields["loop_type"]["value"].startswith("full loop") and fields["loop_position"]["value"]
        assert fields["quality_grade"]["value"] == "DIN 2097 grade 2"
        assert (
            fields["cycles"]["value"] == "1e+06" and "its coil's duty record" in fields["cycles"]["note"]
        )  # the demo states its duty
        assert fields["peening"]["value"] == "not peened"
        assert {"fatigue_body", "fatigue_hook_bending", "fatigue_hook_torsion"} <= set(fields)


@pytest.mark.slow  # the demo's design: ~10 s
def test_order_json_validates_and_says_why_a_field_is_empty(demo):
    _, folder = demo
    order = json.loads((folder / "order.json").read_text())
    jsonschema.validate(order, ORDER_SCHEMA)
    for spring in order["springs"]:
        for field in spring["fields"]:
            if field["value"] is None:
                assert field["note"], (spring["name"], field["key"])
        assert _fields(spring)["finish"]["value"] is None and "--finish" in _fields(spring)["finish"]["note"]


@pytest.mark.slow  # the demo's design: ~10 s
def test_drawing_parses_and_carries_the_dimensions(demo):
    design, folder = demo
    record = json.loads(design.read_text())
    for entry in record["design"]:
        root = ElementTree.parse(folder / f"{entry['name']}.svg").getroot()
        assert root.tag == f"{SVG}svg" and root.get("width") == "297mm" and root.get("height") == "210mm"
        texts = [element.text or "" for element in root.iter(f"{SVG}text")]
        d, D, n = entry["wire_diameter"], entry["mean_diameter"], entry["active_coils"]
        free = d * (n + 1) + 2 * (D - d)
        # two loads are specified, so L0 is a reference dimension (DIN 2099): in parentheses, no tolerance
        assert f"L0 ({free * 1e3:.2f})" in texts, texts
        assert any(text.startswith(f"De ⌀{(D + d) * 1e3:.2f} ±") for text in texts)
        assert any(text.startswith(f"d = {d * 1e3:.2f} ±") for text in texts)
        assert any(text == f"LK ({d * (n + 1) * 1e3:.2f})" for text in texts)
        _, f1, _, f2 = _reference_loads(record, entry)
        assert f"{f1:.2f}" in texts and f"{f2:.2f}" in texts  # the loads table
        assert any(text.startswith("Scale ") for text in texts)
        assert len(list(root.iter(f"{SVG}polygon"))) > 10  # the coil's turns and the arrowheads


@pytest.mark.slow  # the demo's design: ~10 s
def test_bom_lists_every_spring_and_anchor(demo):
    design, folder = demo
    record = json.loads(design.read_text())
    rows = list(csv.DictReader((folder / "bom.csv").read_text().splitlines()))
    springs = [row for row in rows if row["category"] == "spring"]
    assert sorted(row["springs"] for row in springs) == sorted(entry["name"] for entry in record["design"])
    assert all(row["quantity"] == "1" for row in springs)
    served = " ".join(row["springs"] for row in rows if row["category"] == "anchor").split()
    assert sorted(served) == sorted(f"{entry['name']}.{end}" for entry in record["design"] for end in "ab")
    for row in rows:
        if row["category"] == "anchor":
            entry = next(e for e in record["design"] if row["springs"].split()[0].startswith(e["name"] + "."))
            end = entry[row["springs"].split()[0].rsplit(".", 1)[1]]
            assert row["body"] == end["body"]
            assert [float(row[k]) for k in ("x_mm", "y_mm", "z_mm")] == pytest.approx(
                [1e3 * v for v in end["point"]], abs=0.006
            )
    assert [int(row["item"]) for row in rows] == list(range(1, len(rows) + 1))
    page = (folder / "order.html").read_text()
    assert "Bill of materials" in page and all(entry["name"] in page for entry in record["design"])


def _single_link(springs: list) -> sb.DesignResult:
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    return sb.DesignResult(sb.DesignProblem(mechanism, sb.Workspace.grid(mechanism, 11), springs), np.zeros(0))


def test_compression_spring_form_controls_the_bore_on_a_rod():
    """A guided compression coil (2 mm wire, D = 20 mm, 12 active coils, L0 = 160 mm) between (0, 0, 0.05) on
    the ground and (0, 0, 0.1) on the link, which turns about x over 120°-180°: its length runs from
    |(0, −0.1 sin 120°, 0.1 cos 120° − 0.05)| = 0.1323 m to 0.15 m at 180°."""
    coil = HelicalCompressionSpring(
        sb.Anchor("universe", [0, 0, 0.05]),
        sb.Anchor("link1", [0, 0, 0.1]),
        "push",
        wire_diameter=2e-3,
        mean_diameter=20e-3,
        active_coils=12.0,
        free_length=0.16,
        guided=True,
    )
    (order,) = spring_orders(_single_link([coil]))
    rate = G_MUSIC * (2e-3) ** 4 / (8 * (20e-3) ** 3 * 12)
    shortest, longest = np.hypot(0.1 * np.sin(2 * np.pi / 3), 0.1 * np.cos(2 * np.pi / 3) - 0.05), 0.15
    assert order.form == "DIN 2099-1 (form A)"
    assert order.field("length_1").value == pytest.approx(longest, rel=1e-9)
    assert order.field("load_1").value == pytest.approx(rate * (0.16 - longest), rel=1e-9)
    assert order.field("load_2").value == pytest.approx(rate * (0.16 - shortest), rel=1e-6)
    assert order.field("controlled_diameter").value == "inner (Di)"
    assert order.field("inner_diameter").value == pytest.approx(18e-3) and order.field("inner_diameter").tolerance
    assert order.field("total_coils").value == 14.0 and order.field("solid_length").value == pytest.approx(28e-3)
    assert order.field("end_type").value.startswith("closed and ground")
    files = order_files(_single_link([coil]), OrderOptions(grade=1, finish="oiled"))
    svg = ElementTree.fromstring(files["push.svg"])
    assert any((text.text or "").startswith("Di ⌀18.00 ±") for text in svg.iter(f"{SVG}text"))
    assert json.loads(files["order.json"])["springs"][0]["tolerances"]["grade"] == 1


def test_routed_spring_bom_has_its_guide_and_cable():
    routed = spring_from_dict(
        {
            "name": "s1",
            "type": "routed",
            "path": [
                {"body": "link1", "point": [0, 0, -0.05]},
                {"body": "link1", "point": [0, 0, 0.2]},
                {"body": "universe", "point": [0, 0.1, 0.3]},
            ],
            "spring": {"wire_diameter": 2e-3, "mean_diameter": 16e-3, "active_coils": 20.0, "initial_tension": 10.0},
            "cable_length": 0.05,
        }
    )
    files = order_files(_single_link([routed]))
    rows = list(csv.DictReader(files["bom.csv"].splitlines()))
    assert [row["category"] for row in rows] == ["spring", "guide", "cable", "anchor", "anchor"]
    assert rows[2]["description"].startswith("cable, 50.0 mm")
    assert rows[1]["body"] == "link1" and float(rows[1]["z_mm"]) == pytest.approx(200.0)


def test_cli_exit_codes(tmp_path, capsys):
    # a coil stretched past its allowable load fails a check: exit 3, nothing written without --partial
    failing = _single_link([overloaded_coil()])
    failing.save(tmp_path / "failing.json")
    out = tmp_path / "failing_order"
    assert main(["order", str(tmp_path / "failing.json"), "-o", str(out)]) == 3
    assert not out.exists()
    assert "nothing written" in capsys.readouterr().err
    assert main(["order", str(tmp_path / "failing.json"), "-o", str(out), "--partial"]) == 3
    assert "fails" in (out / "order.html").read_text() and json.loads((out / "order.json").read_text())["partial"]
    assert "marked partial" in capsys.readouterr().err
    # ideal springs only: nothing a maker can quote, exit 2 and one line
    ideal = _single_link(
        [
            sb.ExtensionSpring(
                sb.Anchor("universe", [0, 0, 0.1]),
                sb.Anchor("link1", [0, 0, 0.2]),
                "i",
                stiffness=50.0,
                free_length=0.05,
            )
        ]
    )
    ideal.save(tmp_path / "ideal.json")
    assert main(["order", str(tmp_path / "ideal.json"), "-o", str(tmp_path / "ideal_order")]) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and "nothing a spring maker can quote" in error[0] and "'i'" in error[0]
    assert not (tmp_path / "ideal_order").exists()
    (tmp_path / "file").write_text("x")
    assert main(["order", str(tmp_path / "failing.json"), "-o", str(tmp_path / "file")]) == 2


def test_the_template_ships_with_the_package():
    template = resources.files("springbalance.results.order") / "templates" / "order.html.j2"
    assert template.is_file()
    pyproject = (ROOT / "pyproject.toml").read_text()
    assert '"results/order/templates/*.j2"' in pyproject and '"jinja2>=3.1"' in pyproject


def test_an_anchor_off_its_link_is_a_bracket_to_design_with_its_load():
    """two_link_planar_collision.urdf: link1's box has its top face at z = 0.02 m (link1's frame), so the anchor
    (0.3, 0, 0.12) stands 100 mm above it, its bracket's foot at (0.3, 0, 0.02). The zero-free-length spring of
    200 N/m from the ground point (0.3, 0, 0.5) is 0.38 m long at shoulder 0: 76 N, 7.6 N·m at the foot."""
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0.3, 0, 0.5]), sb.Anchor("link1", [0.3, 0, 0.12]), "far", stiffness=200.0
    )
    problem = sb.DesignProblem(mechanism, sb.Workspace.from_array(mechanism, np.zeros((1, 2))), [spring])
    from springbalance.results.order.bom import bom_rows

    rows = bom_rows(sb.DesignResult(problem, np.zeros(0)), [])  # a law, not a coil: the anchors all the same
    ground, link = (row for row in rows if row["category"] == "anchor")
    assert ground["body"] == "universe" and ground["description"] == "anchor bracket with a pin"
    assert link["description"] == "anchor bracket with a pin, 100 mm off link1"
    assert "its shortest foot on link1 at (300.0, 0.0, 20.0) mm" in link["notes"]
    assert "far.b pulls with up to 76 N, 7.6 N·m at the foot" in link["notes"]
