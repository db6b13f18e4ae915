"""Multipliers of the constraint rows, between the solver's scaled rows and the NLP's rows.

The solvers' least squares see N·n_c sample rows ``c / scale`` (sample by sample), then the linear rows;
the NLP of :meth:`~springbalance.design.problem.DesignProblem.assemble` has the rows that depend on the
sample once per sample, unscaled, those that do not once, then the objective's own rows and the linear
rows. ``blocks``: the torque model's constraint blocks (offset, scale, per_sample); ``n``: the samples.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from springbalance.design.torque_model import ConstraintBlock


def nlp_row_multipliers(blocks: Sequence[ConstraintBlock], n: int, scaled: np.ndarray, n_rows: int) -> np.ndarray:
    """Multipliers of the rows of :meth:`assemble` (≥ 0, for a cost in the least-squares scale) from
    those of the solver's scaled rows ``c / scale``: ``scaled`` holds N·n_c sample rows (sample by
    sample), then the linear rows.

    The NLP's sample rows are unscaled, so ``ν = ν_scaled / scale``; a row that does not depend on
    the sample enters the NLP once and takes the sum over the samples; the objective's own rows
    (epigraphs) get 0. ``n_rows``: the NLP's row count.
    """
    scale, varying, constant = _row_layout(blocks)
    scaled = np.asarray(scaled, dtype=float)
    per_sample = scaled[: n * scale.size].reshape(n, scale.size) / scale
    linear = scaled[n * scale.size :]
    parts = [per_sample[:, varying].reshape(-1), per_sample[:, constant].sum(axis=0)]
    objective_rows = n_rows - sum(part.size for part in parts) - linear.size
    if objective_rows < 0:
        raise ValueError(f"{n_rows} NLP rows, fewer than the {n_rows - objective_rows} rows of the multipliers")
    return np.concatenate(parts + [np.zeros(objective_rows), linear])


def scaled_row_multipliers(blocks: Sequence[ConstraintBlock], n: int, nlp: np.ndarray, n_linear: int) -> np.ndarray:
    """The inverse of :meth:`nlp_row_multipliers`: multipliers of the solver's scaled rows (N·n_c
    sample rows, sample by sample, then ``n_linear`` linear rows) from those of the NLP's rows
    (≥ 0). A row that does not depend on the sample is shared evenly by the samples."""
    scale, varying, constant = _row_layout(blocks)
    nlp = np.asarray(nlp, dtype=float)
    per_sample = np.zeros((n, scale.size))
    per_sample[:, varying] = nlp[: n * len(varying)].reshape(n, len(varying))
    per_sample[:, constant] = nlp[n * len(varying) : n * len(varying) + len(constant)] / n
    linear = nlp[nlp.size - n_linear :] if n_linear else np.zeros(0)
    return np.concatenate([(per_sample * scale).reshape(-1), linear])


def _row_layout(blocks: Sequence[ConstraintBlock]) -> tuple[np.ndarray, list, list]:
    """``(scales, varying, constant)`` of the constraint blocks: each block's row scale,
    and the blocks whose row depends on the sample and those whose row does not."""
    return (
        np.array([block.scale for block in blocks]),
        [block.offset for block in blocks if block.per_sample],
        [block.offset for block in blocks if not block.per_sample],
    )
