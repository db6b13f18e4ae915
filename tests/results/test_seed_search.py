"""Which seed's design is kept (results/seed_search.py): passing first, then fewest failures, then lowest objective,
then the seed listed first; and the record's round trip."""

from __future__ import annotations

from springbalance.results.seed_search import SeedRun, SeedSearch, best_run


def test_a_passing_design_beats_a_lower_one_that_fails():
    runs = [SeedRun(0, 0.5, ("overlap",)), SeedRun(1, 0.9), SeedRun(2, 0.7)]
    assert best_run(runs).seed == 2


def test_of_failing_designs_the_one_with_fewest_failures_is_kept_then_the_lowest():
    runs = [
        SeedRun(0, 0.5, ("overlap", "not_verified")),
        SeedRun(1, 0.9, ("overlap",)),
        SeedRun(2, 0.8, ("worse_joint",)),
    ]
    assert best_run(runs).seed == 2


def test_equal_designs_keep_the_seed_listed_first():
    runs = [SeedRun(7, 0.5), SeedRun(3, 0.5), SeedRun(1, 0.6)]
    assert best_run(runs).seed == 7


def test_a_seed_without_a_design_is_never_kept():
    runs = [SeedRun(0, None, error="no start gave a feasible design"), SeedRun(1, 3.0, ("overlap",))]
    assert best_run(runs).seed == 1
    assert best_run(runs[:1]) is None


def test_the_record_round_trips_and_a_damaged_one_is_none():
    search = SeedSearch((SeedRun(0, 1.25, ("overlap",), 2.5), SeedRun(1, None, (), 0.5, "infeasible")), kept=0)
    assert SeedSearch.from_dict(search.to_dict()) == search
    assert search.seconds == 3.0
    assert SeedSearch.from_dict({"kept": 0}) is None
    assert SeedSearch.from_dict([1, 2]) is None
    lines = search.lines("N·m")
    assert lines[0].startswith("  solved at seeds 0, 1 (3.0 s); kept the design of seed 0")
    assert "seed 0: 1.25 N·m, overlap  ← kept" in lines[1]
    assert "seed 1: no design (infeasible)" in lines[2]
    assert search.summary("N·m") == "Solved at 2 seeds, the design of seed 0 kept (0: 1.25 N·m, overlap; 1: no design)."
