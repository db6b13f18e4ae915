r"""The Pareto plot of a study: every solved topology as a point, the front drawn, each point a link.

A point is a solved topology: ``x`` its number of springs (or, when every solved design's springs
have a mass, the springs' total mass [kg]), ``y`` its peak residual relative to the unbalanced peak
[1], on a log axis. A point is **on the front** when no other point is at least as good on both
axes and better on one:

.. math:: p \text{ dominated} \iff \exists q:\ x_q \le x_p,\ y_q \le y_p,\ (x_q, y_q) \ne (x_p, y_p).

The front is drawn as a staircase (a design with more springs is only worth it below the step) and
its points are ringed. With ``x`` the spring count, the points of one count are spread a little
to the right (by residual, the best at the count itself, the worst at +0.4) so that none hides another;
the count is the integer part.
Buildable designs (every spring a coil whose spec sheet passes) are filled, the others hollow.

Each point links (SVG ``<a>``, its tooltip the topology) to its design's page given by ``links``
(a relative address by the record's ``id``), so the inline SVG of ``report.html`` opens the
design's report when clicked.
"""

from __future__ import annotations

import html
import io
from typing import TYPE_CHECKING, Mapping, Sequence

from springbalance.results.plots import new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: the smallest residual drawn on the log axis (an exact design's 1e-13 is drawn at its value)
FLOOR = 1e-16
#: the sideways spread of the points of one spring count
SPREAD = 0.4


def pareto_front(points: Sequence[tuple[float, float]]) -> list[int]:
    """Indices of the non-dominated ``points`` (x, y), both to be minimised (see the module), by x then y."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], float("inf")
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def by_mass(records: Sequence[Mapping]) -> bool:
    """True when every record's springs have a mass (the plot's x is then the total spring mass [kg])."""
    return bool(records) and all(record.get("spring_mass") is not None for record in records)


def _positions(records: Sequence[Mapping], mass: bool) -> list[float]:
    """Each point's drawn x: its mass, or its count spread sideways by residual within the count."""
    if mass:
        return [float(record["spring_mass"]) for record in records]
    x = [float(record["count"]) for record in records]
    for count in set(x):
        members = sorted(
            (i for i in range(len(records)) if x[i] == count), key=lambda i: records[i]["relative_residual"]
        )
        if len(members) > 1:
            for rank, i in enumerate(members):
                x[i] = count + SPREAD * rank / (len(members) - 1)
    return x


def _title(record: Mapping) -> str:
    springs = " + ".join(record.get("springs", []))
    pruned = f" (pruned: {record['pruned']})" if record.get("pruned") else ""
    return f"{springs}: residual {record['relative_residual']:.3g} of the unbalanced peak{pruned}"


def pareto_figure(records: Sequence[Mapping], links: Mapping[str, str] | None = None) -> Figure:
    """The Pareto plot of the solved ``records`` (rows of ``results.csv`` with ``id``, ``count``,
    ``relative_residual``, ``spring_mass``, ``buildable``); ``links`` maps a record's id to the address its
    point opens. The point collections have the gids ``buildable`` and ``other``, the front's rings
    ``front`` and its staircase ``front-line``."""
    links = links or {}
    mass = by_mass(records)
    x = _positions(records, mass)
    y = [max(float(record["relative_residual"]), FLOOR) for record in records]
    figure = new_figure(figsize=(6.8, 4.2), layout="constrained")
    axes = figure.add_subplot()
    for gid, buildable, label in (
        ("buildable", True, "buildable (every spring a coil that passes its spec sheet)"),
        ("other", False, "not known to be buildable (ideal springs, or a coil fails its spec sheet)"),
    ):
        chosen = [i for i, record in enumerate(records) if bool(record.get("buildable")) == buildable]
        if not chosen:
            continue
        points = axes.scatter(
            [x[i] for i in chosen],
            [y[i] for i in chosen],
            s=40,
            facecolors="C0" if buildable else "none",
            edgecolors="C0",
            label=label,
            zorder=3,
        )
        points.set_gid(gid)
        points.set_urls([links.get(records[i]["id"]) for i in chosen])
    front = pareto_front(
        [(float(r["spring_mass"] if mass else r["count"]), float(r["relative_residual"])) for r in records]
    )
    if front:
        fx, fy = [x[i] for i in front], [y[i] for i in front]
        (line,) = axes.step([*fx, max(x) + (0.05 if mass else 0.5)], [*fy, fy[-1]], where="post", color="C1")
        line.set_gid("front-line")
        rings = axes.scatter(fx, fy, s=130, facecolors="none", edgecolors="C1", linewidths=1.6, label="Pareto front")
        rings.set_gid("front")
        rings.set_urls([links.get(records[i]["id"]) for i in front])
    axes.set_yscale("log")
    if mass:
        axes.set_xlabel("total spring mass [kg]")
    else:
        counts = sorted({int(record["count"]) for record in records})
        axes.set_xticks(counts)
        axes.set_xlim(min(counts) - 0.4, max(counts) + 0.8)
        axes.set_xlabel("number of springs")
    axes.set_ylabel("peak residual / unbalanced peak (a ratio)")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(loc="best", fontsize=8)
    return figure


def pareto_svg(records: list[dict], links: Mapping[str, str] | None = None) -> str:
    """The Pareto plot (:func:`pareto_figure`) as inline SVG text; each linked point carries a ``<title>``
    (its topology and residual), shown when the pointer rests on it."""
    figure = pareto_figure(records, links)
    stream = io.StringIO()
    figure.savefig(stream, format="svg")
    text = stream.getvalue()
    text = text[text.index("<svg") :]
    titles = {links[r["id"]]: _title(r) for r in records if links and r["id"] in links}
    for href, title in titles.items():
        anchor = f'<a xlink:href="{html.escape(href)}" target="_blank">'
        text = text.replace(anchor, f"{anchor}<title>{html.escape(title)}</title>")
    return text
