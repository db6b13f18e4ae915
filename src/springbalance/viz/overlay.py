"""What the scene's pages (the static ``scene.html`` and the live page of ``view``) show over meshcat's
canvas: the springs' name labels, placed so that they do not overlap, and the control that shows the
anchor regions.

**Labels.** Each spring's name is an HTML element that follows a point of the scene (the node
``/meshcat/springbalance/labels/<name>``, which the animation moves with the spring's middle). On
every drawn frame a small script projects each point with meshcat's camera and places the labels
greedily, from the top of the view down: a label takes the first spot, beside its point, on rings
of :data:`RINGS` px, that overlaps neither a label already placed nor the page's panels (colour legend,
anchor regions' checkbox, pose slider); a label
moved off its ring-0 spot gets a leader line to its point. Where no spot is free (a crowded view)
the label shrinks to a dot at its point, or at the nearest free spot on rings 11 px apart (with a leader
line; where the panels leave no free spot, the nearest spot off the other labels), and shows its name
while the pointer is over it. Each label
records where it is drawn (``data-box="left,top,right,bottom"`` [px], ``data-mode="label"|"dot"``),
so a test can read the layout from the DOM.

**Anchor regions** are hidden when the page opens (the node ``/meshcat/springbalance/regions``);
the checkbox "anchor regions" (or the page address ending in ``#regions``) shows them.

The page needs no server and no network: the script is inline and uses meshcat's own viewer
(the page's ``viewer``).
"""

from __future__ import annotations

import json
from collections.abc import Sequence

from springbalance.viz.meshcat_glue import ROOT

#: Distances [px] from a label's point to the rings of spots tried for it.
RINGS = (10, 30, 56, 90)

_STYLE = """<style>
#springbalance-labels{position:fixed;left:0;top:0;width:100vw;height:100vh;pointer-events:none;z-index:5;
overflow:hidden}
#springbalance-labels svg{position:absolute;left:0;top:0;width:100%;height:100%}
#springbalance-labels line{stroke:#555;stroke-width:1}
.sb-label{position:absolute;font:13px sans-serif;color:#111;white-space:nowrap;padding:0 3px;
background:rgba(255,255,255,0.72);border-radius:3px;line-height:16px}
.sb-label.sb-flag{color:#c00000;font-weight:bold}
.sb-label.sb-dot{font-size:0;width:9px;height:9px;padding:0;border-radius:5px;background:#333;
pointer-events:auto;cursor:default}
.sb-label.sb-dot:hover{font-size:13px;width:auto;height:auto;padding:0 3px;background:#fff;z-index:20}
#springbalance-controls{position:fixed;left:8px;bottom:8px;z-index:10;background:rgba(255,255,255,0.85);
border-radius:4px;padding:4px 8px;font:12px sans-serif;color:#222}
</style>"""

_SCRIPT = """<script>
(function () {
  var SPECS = __SPECS__, RINGS = __RINGS__, REGIONS = __REGIONS__;
  var layer = document.getElementById("springbalance-labels"), svg = layer.querySelector("svg");
  var toggle = document.getElementById("springbalance-regions-toggle");
  if (toggle && location.hash.indexOf("regions") >= 0) { toggle.checked = true; }
  var DIRS = [[0, -1], [1, -1], [-1, -1], [1, 0], [-1, 0], [0, 1], [1, 1], [-1, 1]];
  var items = SPECS.map(function (spec) {
    var el = document.createElement("div");
    el.className = "sb-label" + (spec.flag ? " sb-flag" : "");
    el.textContent = spec.name; el.title = spec.name; el.setAttribute("data-name", spec.name);
    layer.appendChild(el);
    var line = document.createElementNS("http://www.w3.org/2000/svg", "line");
    svg.appendChild(line);
    return {spec: spec, el: el, line: line, last: 0};
  });
  function free(box, taken, w, h) {
    if (box[0] < 0 || box[1] < 0 || box[2] > w || box[3] > h) { return false; }
    for (var k = 0; k < taken.length; k++) {
      var t = taken[k];
      if (box[0] < t[2] && t[0] < box[2] && box[1] < t[3] && t[1] < box[3]) { return false; }
    }
    return true;
  }
  function spots(x, y, w, h, rings) {
    var out = [];
    (rings || RINGS).forEach(function (d) {
      DIRS.forEach(function (o) {
        var cx = x + (o[0] ? o[0] * (d + w / 2) : 0), cy = y + (o[1] ? o[1] * (d + h / 2) : 0);
        out.push([cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2]);
      });
    });
    return out;
  }
  function project(path, camera, W, H) {
    var node = viewer.scene_tree.find(path).object;
    node.updateWorldMatrix(true, false);
    var v = new camera.position.constructor();
    v.setFromMatrixPosition(node.matrixWorld);
    v.project(camera);
    return {x: (v.x + 1) / 2 * W, y: (1 - v.y) / 2 * H, behind: v.z > 1};
  }
  function place() {
    var camera = viewer.camera, W = layer.clientWidth, H = layer.clientHeight;
    camera.updateMatrixWorld();
    var taken = [], placed = [];  // panels and labels; labels only
    ["springbalance-legend", "springbalance-controls", "springbalance-poses"].forEach(function (id) {
      var e = document.getElementById(id);
      if (e) { var r = e.getBoundingClientRect(); taken.push([r.left, r.top, r.right, r.bottom]); }
    });
    var points = items.map(function (item) { return project(item.spec.path, camera, W, H); });
    var order = items.map(function (_, i) { return i; });
    order.sort(function (i, j) { return points[i].y - points[j].y; });
    order.forEach(function (i) {
      var item = items[i], p = points[i], el = item.el;
      el.classList.remove("sb-dot");
      var w = el.offsetWidth, h = el.offsetHeight, all = spots(p.x, p.y, w, h), chosen = -1;
      if (free(all[item.last], taken, W, H)) { chosen = item.last; }
      for (var k = 0; chosen < 0 && k < all.length; k++) { if (free(all[k], taken, W, H)) { chosen = k; } }
      var box;
      if (chosen >= 0 && !p.behind) {
        item.last = chosen; box = all[chosen];
        el.setAttribute("data-mode", "label");
      } else {
        el.classList.add("sb-dot");
        var far = [];
        for (var d = 6; d < W + H; d += 11) { far.push(d); }
        var dots = spots(p.x, p.y, 9, 9, far);
        box = [p.x - 4.5, p.y - 4.5, p.x + 4.5, p.y + 4.5];
        var m = 0, fallback = null;
        for (; m < dots.length && !free(box, taken, W, H); m++) {
          if (fallback === null && free(box, placed, W, H)) { fallback = box; }  // off the labels, on a panel
          box = dots[m];
        }
        if (!free(box, taken, W, H) && fallback !== null) { box = fallback; }
        el.setAttribute("data-mode", "dot");
      }
      el.style.left = box[0] + "px"; el.style.top = box[1] + "px";
      taken.push(box); placed.push(box);
      el.setAttribute("data-box", box.map(Math.round).join(","));
      var moved = chosen >= DIRS.length || el.classList.contains("sb-dot");
      var lx = Math.min(Math.max(p.x, box[0]), box[2]), ly = Math.min(Math.max(p.y, box[1]), box[3]);
      item.line.setAttribute("x1", p.x); item.line.setAttribute("y1", p.y);
      item.line.setAttribute("x2", moved ? lx : p.x); item.line.setAttribute("y2", moved ? ly : p.y);
    });
  }
  function regions() {
    if (!toggle) { return; }
    var node = viewer.scene_tree.find(REGIONS);
    if (node.object.visible !== toggle.checked) { node.set_property("visible", toggle.checked); viewer.set_dirty(); }
  }
  function loop() {
    try { if (typeof viewer !== "undefined" && viewer.camera) { regions(); place(); } }
    catch (error) { document.body.setAttribute("data-springbalance-error", String(error)); }
    requestAnimationFrame(loop);
  }
  loop();
})();
</script>"""


def label_path(name: str) -> list[str]:
    """The meshcat scene-tree path of the node that a spring's name label follows."""
    return ["meshcat", ROOT, "labels", name]


def overlay_html(labels: Sequence[tuple[str, bool]], regions: bool) -> str:
    """The HTML (style, label layer, controls and script) that goes before the static page's
    ``</body>``: ``labels`` are (spring name, flagged) pairs (a flagged spring's label is red and
    bold); ``regions`` adds the "anchor regions" checkbox."""
    specs = [{"name": name, "path": label_path(name), "flag": bool(flag)} for name, flag in labels]
    controls = ""
    if regions:
        controls = (
            '<div id="springbalance-controls"><label><input type="checkbox" id="springbalance-regions-toggle"> '
            "anchor regions</label></div>"
        )
    script = (
        _SCRIPT.replace("__SPECS__", json.dumps(specs).replace("</", "<\\/"))
        .replace("__RINGS__", json.dumps(list(RINGS)))
        .replace("__REGIONS__", json.dumps(["meshcat", ROOT, "regions"]))
    )
    return f'{_STYLE}<div id="springbalance-labels"><svg></svg></div>{controls}{script}'
