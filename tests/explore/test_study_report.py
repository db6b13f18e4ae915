"""The study report compares: the Pareto plot draws every solved topology and the front (the non-dominated
points, found here by brute force over all pairs), each point links to its design, and a spring count that
pruning leaves unsolved still gets its best approximate design from a few pruned topologies, or says why not.

The ranking's expectation is physics: on the three-link chain with zero-free-length springs only a spring from
the ground carries weight (a spring between two links is an internal force: it cannot lift the arm), so the
three one-spring topologies solved for an approximate design are the three springs from the ground.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest
import yaml

from springbalance.errors import InputError
from springbalance.explore import load_study
from springbalance.explore.pareto import pareto_figure, pareto_svg
from study_report_helpers import Links, assert_links_resolve

ROOT = Path(__file__).resolve().parents[2]
THREE_LINK = ROOT / "examples" / "explore_three_link.yaml"


def _records(mass: bool = False) -> list[dict]:
    rng = np.random.default_rng(7)
    records = []
    for number, count in enumerate([1, 1, 1, 2, 2, 2, 2, 3, 3, 3]):
        records.append(
            {
                "id": f"t{number}",
                "count": count,
                "springs": [f"c{i}" for i in range(count)],
                "relative_residual": float(10 ** rng.uniform(-12, 0)),
                "spring_mass": float(rng.uniform(0.05, 0.5)) if mass else None,
                "buildable": bool(number % 2),
            }
        )
    return records


def _non_dominated(records: list[dict], key: str) -> set[str]:
    """Brute force: a record is dominated when another is no worse on both axes and better on one."""
    out = set()
    for p in records:
        dominated = any(
            q[key] <= p[key]
            and q["relative_residual"] <= p["relative_residual"]
            and (q[key], q["relative_residual"]) != (p[key], p["relative_residual"])
            for q in records
        )
        if not dominated:
            out.add(p["id"])
    return out


@pytest.mark.parametrize("mass", [False, True])
def test_the_front_is_the_non_dominated_points_and_every_point_links(mass):
    records = _records(mass)
    links = {record["id"]: f"designs/{record['id']}/report.html" for record in records}
    figure = pareto_figure(records, links)
    axes = figure.axes[0]
    by_gid = {artist.get_gid(): artist for artist in axes.collections + axes.lines}
    drawn = {}
    for gid in ("buildable", "other"):
        points = by_gid[gid]
        for (x, y), url in zip(points.get_offsets(), points.get_urls()):
            drawn[url.split("/")[1]] = (x, y)
    assert set(drawn) == {record["id"] for record in records}  # every solved topology is a point
    for record in records:
        x, y = drawn[record["id"]]
        assert y == pytest.approx(record["relative_residual"], rel=1e-12)
        if mass:
            assert x == pytest.approx(record["spring_mass"])
        else:
            assert int(x) == record["count"] and x - record["count"] <= 0.4 + 1e-12
    front = {url.split("/")[1] for url in by_gid["front"].get_urls()}
    key = "spring_mass" if mass else "count"
    assert front == _non_dominated(records, key)
    # the staircase passes through every front point, descending
    line = by_gid["front-line"]
    ys = line.get_ydata()
    assert all(b <= a for a, b in itertools.pairwise(ys))
    for i in front:
        assert np.isclose(ys, drawn[i][1], rtol=1e-12).any()
    assert axes.get_yscale() == "log"
    assert axes.get_xlabel() == ("total spring mass [kg]" if mass else "number of springs")
    if not mass:
        assert list(axes.get_xticks()) == [1, 2, 3]


def test_the_svg_points_are_links_with_a_tooltip():
    records = _records()
    links = {record["id"]: f"designs/{record['id']}/report.html" for record in records}
    svg = pareto_svg(records, links)
    parser = Links()
    parser.feed(svg)
    # one link per point, and again per ringed front point
    assert set(parser.svg) == set(links.values())
    assert len(parser.svg) == len(records) + len(_non_dominated(records, "count"))
    assert svg.count("<title>c0 + c1 + c2: residual") >= 3


def test_counts_left_unsolved_by_pruning_get_a_few_pruned_topologies(tmp_path):
    study = load_study(THREE_LINK)
    pruned = [task for task in study.tasks if task.pruned]
    by_count = {count: [set(task.labels) for task in pruned if task.count == count] for count in (1, 2, 3)}
    assert sorted(by_count[1], key=sorted) == [{"universe→link1"}, {"universe→link2"}, {"universe→link3"}]
    assert len(by_count[2]) == 3 and all(any(s.startswith("universe→") for s in labels) for labels in by_count[2])
    assert by_count[3] == []  # four three-spring topologies may balance exactly: no approximation needed
    assert all(task.pruned.startswith(("unreachable: ", "degenerate: ")) for task in pruned)
    # 0 turns it off: only the exact attempts
    none = load_study(_with(tmp_path, approximate=0))
    assert not any(task.pruned for task in none.tasks) and len(none.tasks) == len(study.tasks) - 6


def _with(folder: Path, **explore) -> Path:
    """The three-link example with ``explore`` changed, written into ``folder``."""
    record = yaml.safe_load(THREE_LINK.read_text())
    record["explore"].update(explore)
    record["mechanism"]["urdf"] = str((THREE_LINK.parent / record["mechanism"]["urdf"]).resolve())
    out = folder / "study.yaml"
    out.write_text(yaml.safe_dump(record, allow_unicode=True))
    return out


@pytest.mark.slow
def test_without_approximations_the_report_says_why_each_count_has_no_design(tmp_path):
    config = _with(tmp_path, approximate=0, reports=False)
    load_study(config).run(tmp_path / "study", progress=False)
    page = (tmp_path / "study" / "report.html").read_text()
    for count in (1, 2):
        assert f"<td>{count} spring(s)</td>" in page
    assert page.count("explore.approximate is 0") == 2
    assert "all 6 topologies pruned" in page and "all 15 topologies pruned" in page
    assert (tmp_path / "study" / "best_3_springs.json").is_file()
    assert not (tmp_path / "study" / "best_1_springs.json").exists()
    # without reports each point opens its design file
    parser = Links()
    parser.feed(page)
    assert parser.svg and all(href.startswith("designs/") and href.endswith(".json") for href in parser.svg)
    assert_links_resolve(tmp_path / "study")


@pytest.mark.parametrize("value", [-1, 1.5, True, "3"])
def test_bad_approximate_is_one_line(value, tmp_path):
    with pytest.raises(InputError, match=r"explore\.approximate must be an integer ≥ 0"):
        load_study(_with(tmp_path, approximate=value))
