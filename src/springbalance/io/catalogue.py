r"""Stock spring catalogues: CSV files of coil springs one can buy (docs/guides/coils-and-stock.md, "Stock springs").

Format: UTF-8 CSV in SI units, one header row naming the columns (in any order; other columns
are ignored), then one part per row. Blank lines and lines starting with ``#`` are skipped.

============== ===== ==========================================================================
column         unit  meaning
============== ===== ==========================================================================
part_number    —     the part's name (unique, non-empty)
type           —     ``extension`` or ``compression``
material       —     a key of :data:`springbalance.springs.sizing.MATERIALS` (``music_wire``, ...)
wire_diameter  m     ``d`` > 0
mean_diameter  m     mean coil diameter ``D`` > ``d``
active_coils   1     ``n`` > 0
free_length    m     ``l0`` > 0 (extension: hooks included)
initial_tension N    ``F_i`` ≥ 0 (extension); 0 for compression springs
rate           N/m   ``k`` > 0, within 2 % of ``G d⁴/(8 D³ n)`` (``G`` of the material)
max_load       N     largest force > 0 (extension: > ``F_i``)
max_length     m     extension: the longest allowed length (> ``l0``); compression: ``l0``
min_length     m     extension: ``l0``; compression: the solid length (< ``l0``)
============== ===== ==========================================================================

:func:`read_catalogue` returns :class:`~springbalance.design.stock.StockPart` records and rejects a
bad file with a one-line :class:`~springbalance.errors.InputError` that names the file, the line
and the column.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import NoReturn

from springbalance.design.stock import STOCK_KINDS, StockPart
from springbalance.errors import InputError
from springbalance.files import read_input_text
from springbalance.springs.sizing import MATERIALS, spring_rate

__all__ = ["COLUMNS", "RATE_TOLERANCE", "StockPart", "read_catalogue"]

#: column name → unit, in the order of :class:`StockPart`.
COLUMNS = {
    "part_number": "",
    "type": "",
    "material": "",
    "wire_diameter": "m",
    "mean_diameter": "m",
    "active_coils": "1",
    "free_length": "m",
    "initial_tension": "N",
    "rate": "N/m",
    "max_load": "N",
    "max_length": "m",
    "min_length": "m",
}
NUMBERS = tuple(column for column, unit in COLUMNS.items() if unit)
#: largest relative difference between the rate column and G d⁴/(8 D³ n).
RATE_TOLERANCE = 0.02
#: relative tolerance of the columns that repeat the free length.
LENGTH_TOLERANCE = 1e-3


def read_catalogue(path: str | Path) -> list[StockPart]:
    """The parts of the stock catalogue at ``path`` (format: module docstring)."""
    path = Path(path)
    label = str(path)
    text = read_input_text(path, "stock catalogue", InputError, encoding="utf-8-sig")
    lines = [
        (number, line)
        for number, line in enumerate(text.splitlines(), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not lines:
        raise InputError(f"{label}: empty stock catalogue; expected a header row with the columns {', '.join(COLUMNS)}")
    try:
        rows = list(csv.reader(line for _, line in lines))
    except csv.Error as error:
        raise InputError(f"{label}: not a valid CSV file: {error}") from None
    header = [cell.strip() for cell in rows[0]]
    header_line = lines[0][0]
    repeated = sorted({name for name in header if name and header.count(name) > 1})
    if repeated:
        raise InputError(f"{label} line {header_line}: column(s) {', '.join(repeated)} appear more than once")
    missing = [column for column in COLUMNS if column not in header]
    if missing:
        raise InputError(
            f"{label} line {header_line}: missing column(s) {', '.join(missing)}; a stock catalogue has "
            f"the columns {', '.join(COLUMNS)}"
        )
    position = {column: header.index(column) for column in COLUMNS}
    parts: list[StockPart] = []
    seen: dict[str, int] = {}
    for (number, _), row in zip(lines[1:], rows[1:]):
        if len(row) != len(header):
            raise InputError(f"{label} line {number}: {len(row)} cells, the header has {len(header)} columns")
        cells = {column: row[index].strip() for column, index in position.items()}
        part = _part(cells, f"{label} line {number}")
        if part.part_number in seen:
            raise InputError(
                f"{label} line {number}, column 'part_number': {part.part_number!r} is already the part of "
                f"line {seen[part.part_number]}"
            )
        seen[part.part_number] = number
        parts.append(part)
    if not parts:
        raise InputError(f"{label}: the stock catalogue holds no parts (only a header row)")
    return parts


def _part(cells: dict[str, str], where: str) -> StockPart:
    """One row → :class:`StockPart`, checked; errors name ``where`` (file and line) and the column."""
    name = cells["part_number"]
    if not name:
        raise InputError(f"{where}, column 'part_number': empty part number")
    where = f"{where} (part {name!r})"

    def fail(column: str, message: str) -> NoReturn:
        raise InputError(f"{where}, column {column!r}: {message}")

    kind = cells["type"]
    if kind not in STOCK_KINDS:
        fail("type", f"unknown spring type {kind!r}; valid: {', '.join(STOCK_KINDS)}")
    material = cells["material"]
    if material not in MATERIALS:
        fail("material", f"unknown material {material!r}; valid: {', '.join(MATERIALS)}")
    values: dict[str, float] = {}
    for column in NUMBERS:
        text = cells[column]
        try:
            value = float(text)
        except ValueError:
            fail(column, f"expected a number [{COLUMNS[column]}], got {text!r}")
        if not math.isfinite(value):
            fail(column, f"expected a finite number [{COLUMNS[column]}], got {text!r}")
        if column == "initial_tension":
            if value < 0:
                fail(column, f"must be ≥ 0 [N], got {text}")
        elif value <= 0:
            fail(column, f"must be > 0 [{COLUMNS[column]}], got {text}")
        values[column] = value
    d, D, n, l0 = values["wire_diameter"], values["mean_diameter"], values["active_coils"], values["free_length"]
    if D <= d:
        fail("mean_diameter", f"{D:g} m must exceed the wire diameter {d:g} m")
    expected = spring_rate(MATERIALS[material].shear_modulus, d, D, n)  # [N/m]
    if abs(values["rate"] - expected) > RATE_TOLERANCE * expected:
        fail(
            "rate",
            f"{values['rate']:.6g} N/m differs by {100 * (values['rate'] / expected - 1):+.1f} % from "
            f"G d⁴/(8 D³ n) = {expected:.6g} N/m of {material} (more than {100 * RATE_TOLERANCE:g} %)",
        )

    def same_length(column: str, meaning: str) -> None:
        if abs(values[column] - l0) > LENGTH_TOLERANCE * l0:
            fail(column, f"{values[column]:g} m must equal free_length {l0:g} m ({meaning})")

    if kind == "extension":
        same_length("min_length", "an extension spring's shortest length is its free length")
        if values["max_length"] <= l0:
            fail("max_length", f"{values['max_length']:g} m must exceed free_length {l0:g} m")
        if values["max_load"] <= values["initial_tension"]:
            fail("max_load", f"{values['max_load']:g} N must exceed initial_tension {values['initial_tension']:g} N")
    else:
        if values["initial_tension"] != 0:
            fail("initial_tension", f"must be 0 for a compression spring, got {cells['initial_tension']}")
        same_length("max_length", "a compression spring's longest length is its free length")
        if values["min_length"] >= l0:
            fail("min_length", f"the solid length {values['min_length']:g} m must be shorter than free_length {l0:g} m")
    return StockPart(name, kind, material, **{column: values[column] for column in NUMBERS})
