"""The pose slider of a scene page (at its bottom right, inside :data:`springbalance.viz.browser.POSES_BOX` for
the shipped examples): a range input that sets the pose of the scene's animation, and an overlay
with each spring's force and each joint's residual torque at that pose (:class:`~springbalance.viz.pose_data.PoseData`,
embedded as JSON).

The overlay shows four significant digits (a magnitude below 1e-9 as 0; the full six-digit value is the
number's ``data-value``). The scene's animation has one key frame per pose, pose ``i`` (1-based on the page) at time ``(i − 1) / fps``
[s]. Moving the slider pauses meshcat's animation and seeks it to that time (``viewer.animator.seek``, the
same call as meshcat's own time scrubber): the arm moves, the springs stretch and change colour, and the
overlay shows that pose's numbers. While the animation plays, the slider and the numbers follow it. The
button next to the slider plays and pauses. ``#pose=K`` at the end of the page's address opens it at pose
``K``. The page exposes ``window.springbalancePoses`` (``data``, ``set(k)``, ``frame()``, ``ready()``; ``k``
0-based) for scripts and tests.

:func:`pose_slider_html` is the fragment a static page gets before its ``</body>``;
:func:`live_page` is the whole page of a live scene (meshcat's viewer, connected to the server that serves
it, plus the legend and the slider).
"""

from __future__ import annotations

import html

from springbalance.viz.pose_data import PoseData, SceneLike, scene_pose_data

#: the element ids of the slider's parts (the tests and ``window.springbalancePoses`` use them)
CONTAINER_ID, SLIDER_ID, LABEL_ID, TABLE_ID, DATA_ID = (
    "springbalance-poses",
    "springbalance-pose-slider",
    "springbalance-pose-label",
    "springbalance-pose-numbers",
    "springbalance-pose-data",
)

_STYLE = """
<style>
#springbalance-poses{position:fixed;right:8px;bottom:8px;width:max-content;max-width:min(400px,calc(100vw - 16px));
  z-index:10;padding:5px 8px;background:rgba(255,255,255,0.85);border-radius:4px;font:11px sans-serif;color:#222;
  box-sizing:border-box}
#springbalance-poses .bar{display:flex;align-items:center;gap:6px}
#springbalance-poses input[type=range]{width:240px;max-width:50vw;margin:0}
#springbalance-poses button{width:26px;height:20px;padding:0;font:11px sans-serif;cursor:pointer}
#springbalance-poses table{border-collapse:collapse;margin-top:2px;font:inherit}
#springbalance-poses th,#springbalance-poses td{padding:0 5px;text-align:right;white-space:nowrap}
#springbalance-poses th.l,#springbalance-poses td.l{text-align:left}
#springbalance-poses th{font-weight:600;border-bottom:1px solid #bbb}
#springbalance-poses summary{cursor:pointer;margin-top:3px;color:#444}
#springbalance-pose-label{min-width:96px}
</style>"""

_SCRIPT = r"""
<script>
(function () {
  "use strict";
  var data = JSON.parse(document.getElementById("springbalance-pose-data").textContent);
  var n = data.q.length, current = -1, pending = null;
  var slider = document.getElementById("springbalance-pose-slider");
  var label = document.getElementById("springbalance-pose-label");
  var button = document.getElementById("springbalance-pose-play");
  var table = document.getElementById("springbalance-pose-numbers");
  function animator() {
    var v = (typeof viewer !== "undefined") ? viewer : null;
    return (v && v.animator && v.animator.actions.length) ? v.animator : null;
  }
  function number(value) {
    if (value === null || value === undefined) { return "n/a"; }
    if (Math.abs(value) < 1e-9) { return "0"; }
    return String(Number(value.toPrecision(4)));
  }
  function cell(text, field, row, unit) {
    var td = document.createElement("td");
    if (field) {
      var span = document.createElement("span");
      span.className = "springbalance-number"; span.dataset.field = field; span.dataset.row = row;
      td.appendChild(span); td.appendChild(document.createTextNode((unit === "\u00b0" ? "" : " ") + unit));
    } else { td.className = "l"; td.textContent = text; }
    return td;
  }
  function header(names) {
    var tr = document.createElement("tr");
    names.forEach(function (name, i) {
      var th = document.createElement("th"); th.textContent = name; if (i === 0) { th.className = "l"; }
      tr.appendChild(th);
    });
    table.appendChild(tr);
  }
  header(["joint", "position", "residual torque", "gravity alone"]);
  data.joints.forEach(function (j, i) {
    var tr = document.createElement("tr"); tr.appendChild(cell(j.name));
    tr.appendChild(cell(null, "q", i, j.unit === "deg" ? "\u00b0" : j.unit));
    tr.appendChild(cell(null, "tau", i, j.torque_unit)); tr.appendChild(cell(null, "gravity", i, j.torque_unit));
    table.appendChild(tr);
  });
  if (data.springs.length) { header(["spring", "length", "force", ""]); }
  data.springs.forEach(function (s, i) {
    var tr = document.createElement("tr"); tr.appendChild(cell(s.name));
    tr.appendChild(cell(null, "length", i, s.length_unit)); tr.appendChild(cell(null, "force", i, s.force_unit));
    tr.appendChild(document.createElement("td"));
    table.appendChild(tr);
  });
  var numbers = table.querySelectorAll(".springbalance-number");
  function show(k) {
    current = k; slider.value = String(k + 1);
    label.textContent = "pose " + (k + 1) + " of " + n;
    numbers.forEach(function (span) {
      var value = data[span.dataset.field][k][Number(span.dataset.row)];
      span.textContent = number(value); span.dataset.value = String(value);
    });
  }
  function buttonText() {
    var a = animator(); button.textContent = (a && a.playing) ? "\u275a\u275a" : "\u25b6";
  }
  function seek(k) {
    show(k);
    var a = animator();
    if (!a) { pending = k; return; }
    pending = null;
    if (a.playing) { a.pause(); }
    var time = k / data.fps;
    a.actions.forEach(function (action) {
      if (!action.isScheduled()) { action.play(); }
      action.paused = false; action.enabled = true;
    });
    a.seek(time); a.display_progress(time); buttonText();
  }
  function follow() {
    var a = animator();
    if (a && pending !== null) { seek(pending); }
    if (a && a.playing) {
      var k = Math.min(n - 1, Math.max(0, Math.round(a.actions[0].time * data.fps)));
      if (k !== current) { show(k); }
    }
    buttonText();
    window.requestAnimationFrame(follow);
  }
  slider.addEventListener("input", function () { seek(Number(slider.value) - 1); });
  button.addEventListener("click", function () {
    var a = animator(); if (!a) { return; }
    if (a.playing) { a.pause(); } else { a.play(); }
    buttonText();
  });
  var match = /(?:^#|&)pose=(\d+)/.exec(window.location.hash);
  var start = match ? Math.min(n, Math.max(1, Number(match[1]))) - 1 : null;
  if (start === null) { show(0); } else { seek(start); }
  if (n < 2) { slider.disabled = true; button.disabled = true; }
  window.springbalancePoses = {
    data: data, set: seek, frame: function () { return current; },
    ready: function () { return animator() !== null && pending === null; }
  };
  window.requestAnimationFrame(follow);
})();
</script>"""


#: the table of numbers starts open when it has at most this many joints and springs in all (the two-link demo
#: has 5); a larger one (the UR5 with 4 springs has 10) starts folded, a click away, as it would cover the arm
OPEN_ROWS = 8


def pose_slider_html(data: PoseData) -> str:
    """The slider, the overlay of numbers, their data (JSON) and their script: an HTML fragment for the end of a
    scene page's ``<body>`` (it drives the page's ``viewer``, meshcat's). The numbers start folded when there
    are more than :data:`OPEN_ROWS` joints and springs."""
    size = max(data.size, 1)
    opened = " open" if len(data.joints) + len(data.springs) <= OPEN_ROWS else ""
    return (
        f"{_STYLE}\n"
        f'<div id="{CONTAINER_ID}" role="group" aria-label="pose slider">'
        f'<div class="bar"><button id="springbalance-pose-play" type="button" title="play or pause">&#9654;</button>'
        f'<input id="{SLIDER_ID}" type="range" min="1" max="{size}" step="1" value="1" '
        f'aria-label="pose ({html.escape(data.title)})">'
        f'<span id="{LABEL_ID}">pose 1 of {size}</span></div>'
        f"<details{opened}><summary>{html.escape(data.title)}</summary>"
        f'<table id="{TABLE_ID}"></table></details></div>\n'
        f'<script type="application/json" id="{DATA_ID}">{data.to_json()}</script>'
        f"{_SCRIPT}\n"
    )


def scene_slider_html(scene: SceneLike, animate: bool = True) -> str:
    """:func:`pose_slider_html` of a :class:`~springbalance.viz.design_scene.DesignScene` (its poses' numbers,
    :func:`~springbalance.viz.pose_data.scene_pose_data`), or "" for a page without animation (nothing to scrub)."""
    return pose_slider_html(scene_pose_data(scene)) if animate else ""


def live_page(data: PoseData, legend: str = "", title: str = "springbalance scene") -> str:
    """The whole page of a live scene: meshcat's viewer (its script from the server's ``/static/``), connected to
    the server's websocket, with ``legend`` (HTML) and the pose slider."""
    return (
        "<!DOCTYPE html>\n<html><head><meta charset=utf-8>"
        f"<title>{html.escape(title)}</title>"
        "<style>body{margin:0}#meshcat-pane{width:100vw;height:100vh;overflow:hidden}</style></head>\n<body>"
        '<div id="meshcat-pane"></div>\n<script src="/static/main.min.js"></script>\n'
        '<script>var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));\n'
        'try { viewer.connect(); } catch (e) { console.info("not connected to the meshcat server: ", e); }</script>\n'
        f"{legend}{pose_slider_html(data)}</body></html>\n"
    )
