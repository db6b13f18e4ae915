"""What the study-report tests share: every link of a study's report.html resolves to a file of the study, and
each solved topology is a point of the Pareto plot that opens its own design's page."""

from __future__ import annotations

import json
from html.parser import HTMLParser
from pathlib import Path


class Links(HTMLParser):
    """The addresses of a page's links: ``href`` of HTML ``<a>``, ``xlink:href`` of the inline SVG's ``<a>``."""

    def __init__(self):
        super().__init__()
        self.html: list[str] = []
        self.svg: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag != "a":
            return
        attributes = dict(attrs)
        if "xlink:href" in attributes:
            self.svg.append(attributes["xlink:href"])
        elif "href" in attributes:
            self.html.append(attributes["href"])


def page_links(path: Path) -> Links:
    parser = Links()
    parser.feed(path.read_text(encoding="utf-8"))
    return parser


def assert_links_resolve(folder: Path) -> None:
    """Every link of ``folder/report.html`` opens a file of the study; the plot has one linked point per solved
    topology (and ringed front points, linked again) opening that topology's design, whose page lists as many
    springs as the topology has."""
    links = page_links(folder / "report.html")
    assert links.svg and links.html
    for href in links.svg + links.html:
        assert not href.startswith(("http:", "https:", "/")), href
        assert (folder / href).is_file(), href
    solved = {}
    for path in (folder / "results").glob("*.json"):
        record = json.loads(path.read_text())
        if record["status"] == "solved":
            solved[record["id"]] = record
    targets = set(links.svg)
    assert len(targets) == len(solved)
    for task_id, record in solved.items():
        target = next(href for href in targets if task_id in href)
        if target.endswith(".html"):
            page = (folder / target).read_text()
            count = record["count"]
            assert f"<td class=l>s{count}</td>" in page and f"<td class=l>s{count + 1}</td>" not in page
        else:
            assert json.loads((folder / target).read_text())["springs"][-1]["name"] == f"s{record['count']}"
