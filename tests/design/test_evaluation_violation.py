"""The largest violation of an evaluated design's rows (springbalance.design.evaluation.Evaluation.max_violation)."""

import numpy as np
import pytest

from springbalance.design.evaluation import ROW_UNITS, Evaluation, row_units
from springbalance.design.solvers.records import FEASIBILITY_TOLERANCE


def evaluated(rows, units=None):
    rows = np.atleast_2d(np.asarray(rows, dtype=float))
    n = rows.shape[0]
    return Evaluation(np.zeros(1), np.zeros((n, 1)), np.zeros(n), np.zeros((n, 1)), np.zeros((n, 1)), rows, units)


class _Block:
    def __init__(self, unit):
        self.unit = unit


def test_a_row_in_mpa_counts_in_units_of_100_mpa():
    """A Panda coil's initial stress 2.6e-6 MPa (2.6 Pa) beyond its band, where IPOPT had succeeded: within the
    feasibility tolerance once counted in 100 MPa; a length row 2.6e-6 m short is not."""
    units = row_units([_Block("m"), _Block("MPa"), _Block("1")])
    assert units.tolist() == [1.0, ROW_UNITS["MPa"], 1.0]
    stress = evaluated([[0.01, -2.56e-6, 0.2]], units)
    assert stress.max_violation == pytest.approx(2.56e-8)
    assert stress.max_violation <= FEASIBILITY_TOLERANCE
    length = evaluated([[-2.56e-6, 0.5, 0.2]], units)
    assert length.max_violation == pytest.approx(2.56e-6)
    assert length.max_violation > FEASIBILITY_TOLERANCE


def test_without_mpa_rows_every_row_counts_as_it_is():
    assert row_units([_Block("m"), _Block("1"), _Block("N")]) is None
    assert evaluated([[0.3, -0.02], [-0.05, 1.0]]).max_violation == pytest.approx(0.05)
    assert evaluated(np.zeros((3, 0))).max_violation == 0.0
