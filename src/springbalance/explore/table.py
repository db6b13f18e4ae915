"""The table of a study's results: ``results.csv``, one row per finished task (:data:`COLUMNS`)."""

from __future__ import annotations

import csv
import io
import json
from typing import Sequence

#: the columns of ``results.csv``
COLUMNS = (
    "id",
    "status",
    "springs",
    "count",
    "grid",
    "objective",
    "objective_value",
    "objective_before",
    "peak_residual",
    "relative_residual",
    "exact",
    "spring_mass",
    "buildable",
    "ok",
    "pruned",
    "failures",
    "seconds",
    "error",
)


def results_csv(rows: Sequence[dict]) -> str:
    """The rows (finished tasks' results) as CSV text: springs joined by " + ", the grid point as JSON."""
    stream = io.StringIO()
    writer = csv.DictWriter(stream, fieldnames=COLUMNS, extrasaction="ignore")
    writer.writeheader()
    for row in rows:
        writer.writerow(
            {
                **row,
                "springs": " + ".join(row.get("springs", [])),
                "grid": json.dumps(row.get("grid", {}), sort_keys=True),
                "failures": " ".join(row.get("failures", [])),
            }
        )
    return stream.getvalue()
