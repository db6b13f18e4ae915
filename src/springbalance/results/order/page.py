"""The order folder of a design: the printable page, its JSON, a drawing per spring and the bill of materials.

``write_order(result, "order/")`` writes

- ``order/order.html``: per helical spring the DIN 2099 form's fields (:mod:`~springbalance.results.order.form`)
  with its drawing, the springs a maker cannot quote, and the bill of materials; rendered with Jinja2 from the
  template ``templates/order.html.j2`` shipped in the package;
- ``order/order.json``: the same record (:data:`~springbalance.results.order.schema.ORDER_SCHEMA` describes it);
- ``order/<spring>.svg``: the dimensioned drawing of each spring (:mod:`~springbalance.results.order.drawing`);
- ``order/bom.csv``: the bill of materials (:mod:`~springbalance.results.order.bom`).

Every file is rendered before the first is written, and each is written atomically
(:func:`springbalance.files.write_text_atomic`): an error leaves no half-written file. A design without a
helical spring has nothing to order: :func:`order_files` raises :class:`~springbalance.errors.InputError`.
"""

from __future__ import annotations

import datetime
import json
import re
from pathlib import Path
from typing import Any

import jinja2

from springbalance._version import __version__
from springbalance.design.evaluated import EvaluatedDesign
from springbalance.errors import InputError
from springbalance.files import write_text_atomic
from springbalance.results.order.bom import COLUMNS, bom_csv, bom_rows, not_quotable
from springbalance.results.order.drawing import spring_svg
from springbalance.results.order.form import OrderOptions, SpringOrder, spring_orders

#: the format of order.json
ORDER_FORMAT = "springbalance-order/1"
#: display unit per SI unit, and the factor from SI
DISPLAY = {"m": ("mm", 1e3), "N/m": ("N/mm", 1e-3), "N": ("N", 1.0), "1": ("", 1.0), "": ("", 1.0)}


def _shown(value: Any, unit: str) -> str:
    """A field's value in its display unit (mm, N/mm, N); texts as they are."""
    if not isinstance(value, float):
        return str(value)
    factor = DISPLAY.get(unit, (unit, 1.0))[1]
    shown = value * factor
    if unit == "1" and abs(shown) >= 1e4:
        return f"{shown:.3g}"
    return f"{shown:.4g}" if unit in ("1", "N/m") else f"{shown:.2f}" if abs(shown) >= 0.1 else f"{shown:.3g}"


def _environment() -> jinja2.Environment:
    """The template environment: the package's templates, HTML escaping, the display filters."""
    environment = jinja2.Environment(
        loader=jinja2.PackageLoader("springbalance.results.order", "templates"),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
    )
    environment.filters["shown"] = _shown
    environment.filters["unit"] = lambda unit: DISPLAY.get(unit, (unit, 1.0))[0]
    return environment


def drawing_name(name: str, taken: set[str]) -> str:
    """The file name of the drawing of spring ``name``: its name with every character but letters, digits,
    ``-``, ``_`` and ``.`` replaced by ``_`` (numbered when two springs would share one), ``.svg``."""
    stem = re.sub(r"[^A-Za-z0-9_.-]", "_", name).strip(".") or "spring"
    candidate, index = f"{stem}.svg", 2
    while candidate in taken:
        candidate, index = f"{stem}_{index}.svg", index + 1
    taken.add(candidate)
    return candidate


def order_record(
    result: EvaluatedDesign, orders: list[SpringOrder], options: OrderOptions, design: str = ""
) -> dict[str, Any]:
    """The record of ``order.json``: the options, per spring its form and drawing file, the springs a maker
    cannot quote, the bill of materials, and (``partial``) why an order of a failing design was written."""
    taken: set[str] = set()
    springs = [{**order.to_dict(), "drawing": drawing_name(order.name, taken)} for order in orders]
    for entry, order in zip(springs, orders):
        entry["states"] = [{"state": state, "length": length, "load": load} for state, length, load in order.loads]
    record: dict[str, Any] = {
        "format": ORDER_FORMAT,
        "design": design,
        "springbalance": __version__,
        "date": datetime.date.today().isoformat(),
        "options": {
            "grade": options.grade,
            "finish": options.finish,
            "direction": options.direction,
            "quantity": options.quantity,
        },
        "springs": springs,
        "not_quotable": not_quotable(result),
        "bom": bom_rows(result, orders, options.quantity),
    }
    if result.partial:
        record["partial"] = result.partial
    return record


def order_files(result: EvaluatedDesign, options: OrderOptions | None = None, design: str = "") -> dict[str, str]:
    """Every file of the order folder of ``result``, rendered: file name → text.

    ``design`` labels the design (its file) on the page and drawings. Raises InputError, naming every spring
    and why, when the design has no helical spring: there is nothing a spring maker can quote.
    """
    options = options or OrderOptions()
    orders = spring_orders(result, options)
    if not orders:
        reasons = "; ".join(f"{row['name']!r}: {row['reason']}" for row in not_quotable(result))
        raise InputError(
            f"{design or 'the design'} has no helical spring: nothing a spring maker can quote ({reasons or 'no springs'})"
        )
    record = order_record(result, orders, options, design)
    files = {entry["drawing"]: spring_svg(order, design) for entry, order in zip(record["springs"], orders)}
    page = (
        _environment()
        .get_template("order.html.j2")
        .render(
            design=design or "design",
            version=__version__,
            date=record["date"],
            grade=options.grade,
            partial=result.partial,
            orders=[
                {
                    "name": order.name,
                    "kind": order.kind,
                    "form": order.form,
                    "fields": order.fields,
                    "drawing": entry["drawing"],
                }
                for entry, order in zip(record["springs"], orders)
            ],
            not_quotable=record["not_quotable"],
            bom=record["bom"],
            bom_columns=COLUMNS,
        )
    )
    files["order.html"] = page
    files["order.json"] = json.dumps(record, indent=1, allow_nan=False) + "\n"
    files["bom.csv"] = bom_csv(record["bom"])
    return files


def write_order(
    result: EvaluatedDesign, folder: str | Path, options: OrderOptions | None = None, design: str = ""
) -> list[Path]:
    """Render the order of ``result`` (:func:`order_files`), then write each file atomically into ``folder``
    (created); returns the paths written, ``order.html`` first."""
    files = order_files(result, options, design)
    folder = Path(folder)
    names = ["order.html", "order.json", "bom.csv"] + [name for name in files if name.endswith(".svg")]
    return [write_text_atomic(folder / name, files[name]) for name in names]
