"""An order a spring maker can quote: per helical spring of a design the fields of DIN 2099-1/-2, a
dimensioned drawing, and a bill of materials of the whole design (docs/guides/ordering.md).

- :mod:`~springbalance.results.order.form`: the form's fields per coil (:func:`spring_orders`);
- :mod:`~springbalance.results.order.tolerances`: the tolerances of the quality grade;
- :mod:`~springbalance.results.order.duty`: the duty (cycles, peening, fatigue safety factors);
- :mod:`~springbalance.results.order.drawing` (with :mod:`~springbalance.results.order.svg`): the drawing;
- :mod:`~springbalance.results.order.bom`: the bill of materials and the springs a maker cannot quote;
- :mod:`~springbalance.results.order.page`: the folder (``order.html`` from a Jinja2 template, ``order.json``,
  the drawings, ``bom.csv``), :func:`write_order`;
- :mod:`~springbalance.results.order.schema`: the JSON schema of ``order.json``.
"""

from __future__ import annotations

from springbalance.results.order.form import OrderOptions, SpringOrder, spring_orders
from springbalance.results.order.page import order_files, write_order

__all__ = ["OrderOptions", "SpringOrder", "order_files", "spring_orders", "write_order"]
