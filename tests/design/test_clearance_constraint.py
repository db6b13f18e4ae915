"""Springs that fit the arm: clearance as a constraint of the optimisation, and mounted anchors.

The arm is urdf/two_link_planar_collision.urdf (link1: box 0.5×0.04×0.04 m centred 0.25 m along
x of its frame; link2: box 0.4×0.03×0.03 m; tool: sphere of radius 0.03 m at link2's tip; both
joints about (0, -1, 0)). The checks here are independent of the optimisation's own machinery:
the clearance report measures the URDF's shapes themselves (not the convex hulls and separating
planes the optimisation uses) at 10× more poses than the design was fitted on, and the mounting
checks compute the distance to link1's box in closed form.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from clearance_helpers import crossing_springs
from springbalance.cli import main
from springbalance.design import verification_loop
from springbalance.design.clearance_distances import pair_distances
from springbalance.design.clearance_fit import DESCENT_BAND, _Checker, _worst, fit_to_arm
from springbalance.design.clearance_round import FALLBACK_STARTS
from springbalance.design.mounts import MOUNT_ACCEPT
from springbalance.design.solvers import Solution, solve_problem
from springbalance.design.verification_loop import _closest_nearby

URDF = Path(__file__).resolve().parents[2] / "urdf"
LINK1_CENTRE, LINK1_HALF = np.array([0.25, 0.0, 0.0]), np.array([0.25, 0.02, 0.02])  # [m], link1 frame
CHECK = 256  # poses the design is fitted on
DENSE = 10 * CHECK  # poses of the independent check


@pytest.fixture(scope="module")
def arm():
    return sb.Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")


@pytest.fixture(scope="module")
def workspace(arm):
    return sb.Workspace.sobol(arm, n=128, seed=0)


@pytest.fixture(scope="module")
def in_plane(arm, workspace):
    """The multi-start's optimum with every anchor in the arm's plane, no clearance asked for (it carries the elbow
    beyond the bare arm's peak, which the pipeline would then hold)."""
    problem = sb.DesignProblem(arm, workspace, crossing_springs(0.0))
    return sb.DesignResult(problem, solve_problem(problem, starts=4, progress=False).x)


def test_the_optimum_without_clearance_passes_through_link2(in_plane):
    report = in_plane.clearance(samples=DENSE)
    row = report.row("s1")
    assert row.distance < 0  # overlap: the spring passes through the arm
    assert row.link in ("link2", "tool")  # link2, or the tool welded to its tip


def test_clearance_fitted_from_a_design_through_link2_keeps_the_margin_at_10x_the_poses(arm, workspace, in_plane):
    margin = 0.005
    problem = sb.DesignProblem(
        arm, workspace, crossing_springs(0.1), clearance=sb.Clearance(margin=margin, check_samples=CHECK)
    )
    start = np.array([in_plane.variables.get(name, 0.0) for name in problem.variables.names])
    assert (
        sb.DesignResult(problem, start).clearance(samples=DENSE).row("s1").distance < 0
    )  # the same design, through link2
    solution, fit, _ = fit_to_arm(
        problem,
        Solution(start, [], "auto", 0, "given"),
        method="auto",
        max_iterations=100,
        tolerance=1e-8,
        polish_iterations=None,
    )
    result = sb.DesignResult(problem, solution.x, fit=fit)
    assert fit.converged and fit.rounds >= 1 and fit.rows > 0
    # the fitted solution keeps the records of the starts it was given (design.json's multi-start spread), not
    # those of its last round's re-solve
    assert solution.starts == [] and (solution.method, solution.seed) == ("auto", 0)
    report = result.clearance(samples=DENSE)  # the URDF's own shapes, 2,560 poses
    assert report.margin == margin and report.poses == DENSE
    for row in report.rows:
        assert row.distance >= margin, str(report)
    print(
        f"\nprice of {margin * 1e3:g} mm clearance: rms {fit.objective_before:.6g} → {fit.objective:.6g} N·m "
        f"({fit.cost_percent:+.3f} %), {fit.rounds} round(s), {fit.rows} rows, {fit.seconds:.2f} s"
    )
    assert fit.objective <= 1.05 * fit.objective_before  # stepping out of the plane costs (almost) nothing


def test_the_search_between_samples_clears_a_design_fitted_on_16_poses(arm, workspace, in_plane):
    """Fitted on 16 poses only (and the 64 of the denser set), the design still keeps the margin at
    2,560: the descent from the closest sampled poses finds the closest approaches between them
    (without it, this design passes through the tool)."""
    margin = 0.005
    problem = sb.DesignProblem(
        arm, workspace, crossing_springs(0.1), clearance=sb.Clearance(margin=margin, check_samples=16)
    )
    start = np.array([in_plane.variables.get(name, 0.0) for name in problem.variables.names])
    solution, fit, _ = fit_to_arm(
        problem,
        Solution(start, [], "auto", 0, "given"),
        method="auto",
        max_iterations=100,
        tolerance=1e-8,
        polish_iterations=None,
    )
    assert fit.converged
    report = sb.DesignResult(problem, solution.x, fit=fit).clearance(samples=DENSE)
    for row in report.rows:
        assert row.distance >= margin, str(report)


def test_fitting_more_starts_keeps_the_best_fit(arm, workspace):
    """With clearance.starts = 3 the loop fits the three best designs of the multi-start and keeps the
    fitted one of lowest objective: never worse than fitting the best start alone, and still clear."""
    margin = 0.005
    results = {}
    for starts in (1, 3):
        clearance = sb.Clearance(margin=margin, check_samples=64, starts=starts)
        results[starts] = sb.solve(
            sb.DesignProblem(arm, workspace, crossing_springs(0.1), clearance=clearance), starts=4, seed=1
        )
    # one start fitted, and the next one too when that fit had to move its design (clearance_round.fall_back)
    # (and the next ones while every fit carries a joint worse than the bare arm: this arm's elbow peak)
    assert results[1].fit.starts <= 1 + FALLBACK_STARTS and results[3].fit.starts >= 3
    assert results[3].fit.converged
    assert results[3].fit.objective <= results[1].fit.objective * (1 + 1e-9)
    # the kept fit carries the elbow worse than the bare arm (its peak): the pipeline holds it, and the verification's
    # re-solve keeps it held (it used to drop the rows and end at the fit's design, worse_joint)
    hold = results[3].joint_hold
    assert hold is not None and hold.held and hold.objective_before == pytest.approx(results[3].fit.objective, rel=1e-9)
    assert results[3].metrics()["objectives"]["rms"]["after"] == pytest.approx(hold.objective, rel=1e-6)
    assert results[3].ok, results[3].failures()
    for row in results[3].clearance(samples=DENSE).rows:
        assert row.distance >= margin


def test_solve_with_clearance_keeps_springs_apart_and_saves_the_fit(arm, workspace, tmp_path):
    """Both springs start on link1 on top of each other; with between_springs they keep the margin
    from each other too (checked by brute force on the segments)."""
    twins = [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", sb.Free([-0.1, -0.1, 0.2], [0.1, 0.1, 0.4], init=[0, 0, 0.3])),
            sb.Anchor("link1", sb.Free([0.1, -0.1, -0.05], [0.5, 0.1, 0.05], init=[0.3, 0, 0])),
            stiffness=sb.Free(0, 5000),
            name=name,
        )
        for name in ("s1", "s2")
    ]
    clearance = sb.Clearance(margin=0.005, check_samples=64, between_springs=True)
    problem = sb.DesignProblem(arm, workspace, twins, clearance=clearance)
    result = sb.solve(problem, starts=1)
    assert result.fit is not None and result.fit.converged
    ends = {}
    poses = sb.Workspace.sobol(arm, n=640, seed=3)
    kinematics = poses.kinematics()
    for record in result.springs:
        a, b = (np.asarray(record[end]["point"]) for end in ("a", "b"))
        link1 = kinematics.body("link1")
        world_b = link1.translation + np.einsum("nij,j->ni", link1.rotation, b)
        ends[record["name"]] = (np.broadcast_to(a, world_b.shape), world_b)
    t = np.linspace(0.0, 1.0, 201)
    smallest = np.inf
    for i in range(poses.size):
        p = ends["s1"][0][i] + t[:, None] * (ends["s1"][1][i] - ends["s1"][0][i])
        q = ends["s2"][0][i] + t[:, None] * (ends["s2"][1][i] - ends["s2"][0][i])
        smallest = min(smallest, float(np.min(np.linalg.norm(p[:, None, :] - q[None, :, :], axis=2))))
    # axis to axis ≥ 2 radii + margin, less the brute-force grid's error (half a step of 0.5 mm)
    assert smallest >= 2 * 0.01 + 0.005 - 1e-3
    path = result.save(tmp_path / "design.json")
    loaded = sb.DesignResult.load(path)
    assert loaded.problem.clearance == clearance
    assert loaded.fit is not None and loaded.fit.rounds == result.fit.rounds


def box_distance(point):
    """Signed distance [m] from a link1-frame point to link1's collision box (closed form)."""
    q = np.abs(np.asarray(point) - LINK1_CENTRE) - LINK1_HALF
    return float(np.linalg.norm(np.maximum(q, 0.0)) + min(np.max(q), 0.0))


def write_config(tmp_path, a, b, clearance=None):
    config = {
        "mechanism": {"urdf": str(URDF / "two_link_planar_collision.urdf")},
        "workspace": {"kind": "sobol", "n": 64},
        "springs": [
            {"name": "s1", "type": "zero_free_length", "a": a, "b": b, "stiffness": {"lower": 0, "upper": 5000}}
        ],
        "solve": {"starts": 2},
    }
    if clearance is not None:
        config["clearance"] = clearance
    path = tmp_path / "config.json"
    path.write_text(json.dumps(config))
    return path


@pytest.mark.parametrize("offset", [0.0, 0.01])
def test_an_anchor_on_collision_lies_on_its_bodys_surface_and_one_on_the_floor_on_the_floor(tmp_path, offset):
    config = write_config(
        tmp_path,
        {"body": "universe", "on": "floor", "box": {"lower": [-0.3, -0.1, -0.1], "upper": [0.3, 0.1, 0.1]}},
        {
            "body": "link1",
            "on": "collision",
            "offset": offset,
            "box": {"lower": [0.1, -0.1, -0.1], "upper": [0.5, 0.1, 0.1]},
        },
    )
    out = tmp_path / "design.json"
    assert main(["design", str(config), "--out", str(out)]) == 0
    record = json.loads(out.read_text())["design"][0]
    assert record["a"]["point"][2] == pytest.approx(0.0, abs=1e-12)  # on the floor z = 0
    assert abs(box_distance(record["b"]["point"]) - offset) <= 1e-3  # offset ± 1 mm from link1's box


def test_an_anchor_on_collision_without_a_box_goes_around_the_geometry(arm, workspace):
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", sb.Free([-0.1, -0.1, 0.1], [0.1, 0.1, 0.3])),
        sb.Anchor("link1", None, on="collision", offset=0.005),
        stiffness=sb.Free(0, 5000),
        name="s1",
    )
    result = sb.solve(sb.DesignProblem(arm, workspace, [spring]), starts=2)
    assert abs(box_distance(result.springs[0]["b"]["point"]) - 0.005) <= 1e-3
    assert result.fit.converged


def test_the_multi_start_without_the_mountings_shows_its_own_progress(arm, workspace, capsys):
    """The free optimum (the mounting rows' linearisation point) is a multi-start of its own: with progress on, it
    has a bar of its own, named, before the multi-start's."""
    from springbalance.pipeline.steps import FREE_OPTIMUM_LABEL

    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", sb.Free([-0.1, -0.1, 0.1], [0.1, 0.1, 0.3])),
        sb.Anchor("link1", None, on="collision", offset=0.005),
        stiffness=sb.Free(0, 5000),
        name="s1",
    )
    sb.solve(sb.DesignProblem(arm, workspace, [spring]), starts=2, progress=True)
    bars = capsys.readouterr().err
    assert FREE_OPTIMUM_LABEL in bars
    assert bars.index(FREE_OPTIMUM_LABEL) < bars.rindex("starts:")  # then the mounted multi-start's own bar


@pytest.mark.parametrize(
    "a, b, clearance, culprit",
    [
        (
            {"body": "universe", "point": [0, 0, 0.3]},
            {"body": "base", "on": "collision"},
            None,
            "body 'base' has no collision geometry",
        ),
        (
            {"body": "universe", "point": [0, 0, 0.3]},
            {"body": "link1", "point": [0.3, 0, 0]},
            {"margin": -0.001},
            "clearance.margin",
        ),
        (
            {"body": "universe", "on": "floor", "box": {"lower": [-0.1, -0.1, 0.1], "upper": [0.1, 0.1, 0.2]}},
            {"body": "link1", "point": [0.3, 0, 0]},
            None,
            "no anchor can reach",
        ),
        (
            {"body": "universe", "point": [0, 0, 0.3]},
            {"body": "link1", "on": "collision", "box": {"lower": [0.2, -0.3, 0.2], "upper": [0.3, 0.3, 0.3]}},
            None,
            "no anchor can reach the mounting surface",
        ),
    ],
)
def test_bad_clearance_and_mounting_input_gets_one_line_naming_the_culprit(tmp_path, capsys, a, b, clearance, culprit):
    config = write_config(tmp_path, a, b, clearance)
    out = tmp_path / "design.json"
    assert main(["design", str(config), "--out", str(out)]) == 2
    error = capsys.readouterr().err.strip()
    assert culprit in error and "Traceback" not in error
    assert len(error.splitlines()) == 1, error
    assert not out.exists()


def test_the_checkers_batched_distances_equal_each_contacts_distance(arm, workspace):
    """The fit's check takes each spring's world ends and capsule placement at all its poses at once, and builds
    each capsule once per pose for all the objects. With no bound to spare coal a query (an infinite threshold),
    its distances equal, bit for bit, those of each pair's contact computed alone at the placed pose (the ends
    from the frames there, coal's witness-point query), objects and springs alike."""
    from springbalance.design.clearance_fit import _Checker

    problem = sb.DesignProblem(
        arm, workspace, crossing_springs(0.02), clearance=sb.Clearance(margin=0.005, between_springs=True)
    )
    checker = _Checker(problem, problem.clearance)
    x = np.asarray(problem.variables.start, dtype=float)
    radius = checker._radii(x)
    pairs = list(checker._pairs())
    assert any(kind == "spring" for kind, *_ in pairs) and any(kind == "object" for kind, *_ in pairs)
    poses = checker.pose_sets[0][:12]
    batched = pair_distances(checker, pairs, x, radius, poses, np.inf)
    for sample, q in enumerate(poses):
        checker.scene.place(q)
        alone = [checker._contact(pair, x, radius)[0].distance for pair in pairs]
        assert batched[sample].tolist() == alone


def test_a_pose_sets_kinematics_are_computed_once_for_every_design_checked(arm, workspace, monkeypatch):
    """Where a pose set puts the arm's frames and objects does not depend on the design: the first check of the set
    computes it (one placement per pose), the checks of other designs (a fit's rounds) take it as it is, and find
    what a new checker finds for them."""
    problem = sb.DesignProblem(
        arm, workspace, crossing_springs(0.02), clearance=sb.Clearance(margin=0.005, between_springs=True)
    )
    checker = _Checker(problem, problem.clearance)
    lower, upper = (np.asarray(bound, dtype=float) for bound in problem.variables.bounds())
    designs = [lower + (upper - lower) * share for share in np.random.default_rng(5).random((3, lower.size))]
    placed = []
    original = checker.scene.object_placements
    monkeypatch.setattr(checker.scene, "object_placements", lambda: placed.append(1) or original())
    found = [checker.measure(x, 1) for x in designs]
    assert len(placed) == len(checker.pose_sets[1])  # the first design's check only
    for x, (below, closest, nearest) in zip(designs, found):
        fresh = _Checker(problem, problem.clearance).measure(x, 1)
        assert below == fresh[0] and closest == fresh[1] and nearest == fresh[2]
    assert len({tuple(sorted(closest.items())) for _, closest, _ in found}) == 3  # three designs, three answers


def test_mounting_rows_are_linearised_where_the_free_optimum_puts_the_anchors():
    """The UR5 with two springs whose four anchors sit 20 mm off its links (shoulder → upper arm, upper arm →
    forearm). A mounting row is a tangent plane of the anchor's offset surface: linearised at the boxes' centres,
    it held every start of the multi-start to planes where the springs could do nothing (the bare arm's RMS,
    14.87 N·m, and 14.54 after the fit's rounds). Linearised at the anchors of the optimum without the
    mountings, projected onto the surfaces, the multi-start itself removes more than 40 % of it."""
    ur5 = sb.Mechanism.from_robot("ur5")
    ranges = {"shoulder_lift_joint": [-np.pi, 0.0], "elbow_joint": [-2.6, 2.6]}
    workspace = sb.Workspace.sobol(ur5, n=128, seed=1, ranges=ranges)
    springs = [
        sb.ExtensionSpring(
            sb.Anchor(a, None, on="collision", offset=0.02),
            sb.Anchor(b, None, on="collision", offset=0.02),
            f"s{i}",
            stiffness=sb.Free(0, 5000),
            free_length=sb.Free(0.05, 1.0),
        )
        for i, (a, b) in enumerate([("shoulder_link", "upper_arm_link"), ("upper_arm_link", "forearm_link")])
    ]
    result = sb.solve(sb.DesignProblem(ur5, workspace, springs), starts=2)
    bare = result.metrics()["objectives"]["rms"]["before"]
    assert result.fit.converged
    assert result.fit.objective_before < 0.6 * bare
    assert result.fit.objective < 0.6 * bare
    assert max(result.fit.mounts.values()) <= MOUNT_ACCEPT


def _ur5_shoulder_springs():
    """Three ideal springs on the UR5 (shoulder → upper arm, shoulder → forearm, upper arm → forearm), at random
    anchors (seed 3) in ±0.3 m boxes: a design that passes through some links at some poses and far from others."""
    ur5 = sb.Mechanism.from_robot("ur5")
    pairs = [("shoulder_link", "upper_arm_link"), ("shoulder_link", "forearm_link"), ("upper_arm_link", "forearm_link")]
    springs = [
        sb.ExtensionSpring(
            sb.Anchor(a, sb.Free([-0.3] * 3, [0.3] * 3)),
            sb.Anchor(b, sb.Free([-0.3] * 3, [0.3] * 3)),
            f"s{i}",
            stiffness=sb.Free(0, 5000),
            free_length=sb.Free(0.05, 1.0),
        )
        for i, (a, b) in enumerate(pairs)
    ]
    clearance = sb.Clearance(margin=0.005, check_samples=96, between_springs=True)
    problem = sb.DesignProblem(ur5, sb.Workspace.sobol(ur5, 16, seed=1), springs, clearance=clearance)
    lower, upper = (np.asarray(bound, dtype=float) for bound in problem.variables.bounds())
    return problem, lower + (upper - lower) * np.random.default_rng(3).random(lower.size)


@pytest.mark.parametrize("setting", ["two_link", "ur5"])
def test_the_checks_bounded_distances_are_coals_wherever_they_count(arm, workspace, setting):
    """The check asks coal only where a lower bound (bounding capsules of the objects) cannot decide. Against
    coal's distance of every pair at every pose, pose by pose as the cuts take it (each spring's ends from its
    frames at the placed pose, its capsule built there): equal, bit for bit, wherever within the margin and descent
    band and at each pair's least; below it (a lower bound) everywhere else. (The check takes the springs' ends and
    capsules of all poses at once.)"""
    if setting == "ur5":
        problem, x = _ur5_shoulder_springs()
    else:
        problem = sb.DesignProblem(
            arm, workspace, crossing_springs(0.02), clearance=sb.Clearance(margin=0.005, between_springs=True)
        )
        x = np.asarray(problem.variables.start, dtype=float)
    checker = _Checker(problem, problem.clearance)
    radius, pairs, poses = checker._radii(x), list(checker._pairs()), checker.pose_sets[0]
    threshold = problem.clearance.margin + DESCENT_BAND
    found = pair_distances(checker, pairs, x, radius, poses, threshold)
    coal_distances = np.empty_like(found)
    for sample, q in enumerate(poses):
        checker.scene.place(q)
        coal_distances[sample] = [checker._contact(pair, x, radius)[0].distance for pair in pairs]
    near = coal_distances <= threshold
    assert near.any() and (~near).any()  # the design comes close at some poses, not at others
    assert np.array_equal(found[near], coal_distances[near])
    assert np.array_equal(found.min(axis=0), coal_distances.min(axis=0))
    assert np.all(found <= coal_distances + 1e-12)
    assert np.all(found[~near] > threshold)
    computed = np.sum(found == coal_distances)
    if setting == "ur5":  # the bounds decide most pairs without coal
        assert computed < 0.5 * found.size


def test_the_verification_also_cuts_each_contact_at_the_closest_approach_near_it(arm, workspace):
    """A contact below the margin at an unseen pose is one sample of a continuum of close poses: the verification
    loop also cuts at the closest approach near it, found by a descent over the joints from its pose, which comes
    no farther than the contact's pose and closer where that pose is not itself a minimum."""
    problem = sb.DesignProblem(
        arm, workspace, crossing_springs(0.02), clearance=sb.Clearance(margin=0.005, between_springs=True)
    )
    x = np.asarray(problem.variables.start, dtype=float)
    checker = _Checker(problem, problem.clearance)
    unseen = checker.add_pose_set(sb.Workspace.sobol(arm, 64, seed=5).joint_values)
    below, _, _ = checker.measure(x, unseen)
    contacts = _worst(below)
    assert contacts
    nearby = _closest_nearby(checker, x, contacts)
    assert nearby and all(key[4] == 2 for key in nearby)  # poses the descent found, in the checker's pose set 2
    for pair in {key[:4] for key in nearby}:
        sampled = min(below[key] for key in contacts if key[:4] == pair)
        assert min(value for key, value in nearby.items() if key[:4] == pair) <= sampled + 1e-12
    assert min(nearby.values()) < min(below[key] for key in contacts) - 1e-6


def test_where_no_re_solve_meets_the_cuts_the_verification_fits_the_design_again(arm, workspace, in_plane, monkeypatch):
    """The verification finds the optimum through link2 at its unseen poses. When no single re-solve with the cuts
    there is feasible (held so here), the loop fits the design to the arm again from where it is, the contacts it
    found watched in every round; the design then holds at the next fresh poses and at 10× the poses."""
    margin = 0.005
    problem = sb.DesignProblem(
        arm, workspace, crossing_springs(0.1), clearance=sb.Clearance(margin=margin, check_samples=CHECK)
    )
    start = np.array([in_plane.variables.get(name, 0.0) for name in problem.variables.names])
    refits = []
    monkeypatch.setattr(verification_loop, "_round", lambda *args: None)
    refit = verification_loop._refit
    monkeypatch.setattr(verification_loop, "_refit", lambda *args: refits.append(1) or refit(*args))
    options = {"method": "auto", "max_iterations": 100, "tolerance": 1e-8, "polish_iterations": None}
    solution, record, fitted = verification_loop.verify_and_resolve(
        problem, Solution(start, [], "auto", 0, "given"), "resolve", **options
    )
    assert refits and record.rounds == len(refits) and record.passed
    assert fitted.linear_rows is not None and fitted.linear_violation(solution.x) <= 1e-6
    assert sb.DesignResult(fitted, solution.x).clearance(samples=DENSE).row("s1").distance >= margin - 1e-6
