"""Open a static scene page in headless Chromium and check what is on the screenshot.

This is how the tests (and ``make demo-check``) make sure that ``scene.html`` really
renders — WebGL included — with no server and no network: Chromium loads the file, runs
for a few seconds of virtual time, and saves a PNG; then what a person looks at is measured:

- :func:`drawn_mask` / :func:`drawn_box`: the pixels where something solid is drawn (they differ
  from the page's background gradient, and survive an opening by a 5×5 square that removes the
  one-pixel grid lines and the strokes of text), and their bounding box;
- :func:`colour_census`: the pixels whose hue is that of the springs' colours, and the drawn pixels
  that are not (the arm, whatever its colours: the UR5's greys as well as the demo's blue), or of
  given arm colours;
- :func:`dump_dom` / :func:`label_boxes`: the page's DOM after its scripts ran, and where the name
  labels were drawn (their ``data-box``, :mod:`springbalance.viz.overlay`).

Run as ``python -m springbalance.viz.browser SCENE.html [--screenshot OUT.png]``: it prints what
it found and exits 0 when the arm and the springs are both on the image, 1 when not, and
77 (the conventional "skipped") when no Chromium is installed.

Chromium is looked up as ``$SPRINGBALANCE_CHROMIUM``, ``chromium``, ``chromium-browser``,
``google-chrome`` and ``google-chrome-stable``. WebGL runs on SwiftShader (software), so no
GPU or display is needed.
"""

from __future__ import annotations

import argparse
import colorsys
import dataclasses
import html
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np

from springbalance.viz.colors import ColorScale

CANDIDATES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
#: Window size of the screenshots [px].
WINDOW = (900, 700)
#: Where the scene page puts its colour legend (left, top, right, bottom) [px]; not counted.
LEGEND_BOX = (0, 0, 300, 90)
#: Where meshcat puts its "Open Controls" bar; not counted.
CONTROLS_BOX = (WINDOW[0] - 260, 0, WINDOW[0], 24)
#: Where the scene page puts its pose slider and its numbers (bottom right, :mod:`springbalance.viz.pose_slider`:
#: up to 13 joints and springs in all, such as a 7-joint arm with 6 springs); not counted.
POSES_BOX = (WINDOW[0] - 400, WINDOW[1] - 240, WINDOW[0], WINDOW[1])
#: Where the scene page puts its "anchor regions" checkbox; not counted.
REGIONS_BOX = (0, WINDOW[1] - 40, 140, WINDOW[1])
#: The scene's background gradient, top and bottom (RGB in [0, 1]; DesignScene.draw sets it).
BACKGROUND = ((1.0, 1.0, 1.0), (0.8, 0.83, 0.88))
#: A pixel is drawn when a channel differs from the background by more than this.
DRAWN_THRESHOLD = 0.15
#: Side [px] of the square that opens the drawn mask (removes grid lines and text strokes).
OPENING = 5


class BrowserError(RuntimeError):
    """Chromium is missing or failed to take the screenshot."""


def find_chromium() -> str | None:
    """Path of a Chromium (or Chrome) executable, or None."""
    override = os.environ.get("SPRINGBALANCE_CHROMIUM")
    if override:
        return shutil.which(override) or (override if os.path.isfile(override) else None)
    for name in CANDIDATES:
        path = shutil.which(name)
        if path:
            return path
    return None


def chromium_command(
    chromium: str,
    page: Path,
    image: Path | None,
    profile: Path,
    window: tuple[int, int] = WINDOW,
    budget_ms: int = 2500,
    fragment: str = "",
) -> list[str]:
    """The command line that renders ``page`` into ``image`` (software WebGL, nothing online), or, with
    ``image`` None, prints its DOM after the scripts ran. ``fragment`` is appended to the page's URL
    (``#regions`` shows the anchor regions)."""
    return [
        chromium,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--disable-extensions",
        "--disable-dev-shm-usage",
        "--hide-scrollbars",
        "--mute-audio",
        f"--user-data-dir={profile}",
        f"--screenshot={image}" if image is not None else "--dump-dom",
        f"--window-size={window[0]},{window[1]}",
        f"--virtual-time-budget={int(budget_ms)}",
        Path(page).resolve().as_uri() + fragment,
    ]


def screenshot(
    page: str | Path,
    image: str | Path,
    window: tuple[int, int] = WINDOW,
    budget_ms: int = 2500,
    timeout: float = 120.0,
    fragment: str = "",
) -> Path:
    """Render ``page`` (its URL plus ``fragment``) in headless Chromium and save a PNG screenshot to ``image``.

    Raises:
        BrowserError: no Chromium, a timeout, or no image written.
    """
    chromium = find_chromium()
    if chromium is None:
        raise BrowserError("Chromium is not installed (looked for " + ", ".join(CANDIDATES) + ")")
    image = Path(image).resolve()
    image.parent.mkdir(parents=True, exist_ok=True)
    if image.exists():
        image.unlink()
    with tempfile.TemporaryDirectory(prefix="springbalance-chromium-") as profile:
        command = chromium_command(chromium, Path(page), image, Path(profile), window, budget_ms, fragment)
        try:
            completed = subprocess.run(command, stdin=subprocess.DEVNULL, capture_output=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise BrowserError(f"Chromium took more than {timeout:g} s to render {page}") from None
    if not image.is_file() or image.stat().st_size == 0:
        tail = completed.stderr.decode("utf-8", "replace").strip().splitlines()[-3:]
        raise BrowserError(f"Chromium wrote no screenshot (exit {completed.returncode}): {' | '.join(tail)}")
    return image


def dump_dom(page: str | Path, window: tuple[int, int] = WINDOW, budget_ms: int = 2500, timeout: float = 120.0) -> str:
    """The DOM (HTML) of ``page`` after headless Chromium ran its scripts for ``budget_ms`` of virtual time.

    Raises:
        BrowserError: no Chromium, a timeout, or no output.
    """
    chromium = find_chromium()
    if chromium is None:
        raise BrowserError("Chromium is not installed (looked for " + ", ".join(CANDIDATES) + ")")
    with tempfile.TemporaryDirectory(prefix="springbalance-chromium-") as profile:
        command = chromium_command(chromium, Path(page), None, Path(profile), window, budget_ms)
        try:
            completed = subprocess.run(command, stdin=subprocess.DEVNULL, capture_output=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise BrowserError(f"Chromium took more than {timeout:g} s to render {page}") from None
    dom = completed.stdout.decode("utf-8", "replace")
    if "<html" not in dom.lower():
        raise BrowserError(f"Chromium printed no DOM for {page} (exit {completed.returncode})")
    return dom


def label_boxes(dom: str) -> dict[str, tuple[str, tuple[float, float, float, float]]]:
    """Where the scene page drew each spring's name label: ``name → (mode, (left, top, right, bottom))``
    [px], mode ``"label"`` or ``"dot"`` (a label shrunk to a dot that shows its name on hover), read from
    the ``data-box`` attributes that the page's script writes (:mod:`springbalance.viz.overlay`)."""
    boxes = {}
    for tag in re.findall(r"<div[^>]*class=\"sb-label[^>]*>", dom):
        attributes = dict(re.findall(r'([\w-]+)="([^"]*)"', tag))
        if "data-box" in attributes:
            box = tuple(float(v) for v in attributes["data-box"].split(","))
            boxes[html.unescape(attributes["data-name"])] = (attributes.get("data-mode", ""), box)
    return boxes  # type: ignore[return-value]


def _load_rgb(image: str | Path) -> np.ndarray:
    from PIL import Image

    with Image.open(image) as picture:
        return np.asarray(picture.convert("RGB"), dtype=float) / 255.0


def drawn_mask(
    image: str | Path | np.ndarray,
    exclude: Iterable[tuple[int, int, int, int]] = (LEGEND_BOX, CONTROLS_BOX, REGIONS_BOX, POSES_BOX),
) -> np.ndarray:
    """Pixels (H×W bool) where something solid is drawn: a channel differs from the background
    gradient (:data:`BACKGROUND`, top to bottom) by more than :data:`DRAWN_THRESHOLD`, after an
    opening by an :data:`OPENING` px square (thin grid lines and the strokes of text go); the boxes
    of ``exclude`` (left, top, right, bottom) [px] are not counted."""
    from scipy import ndimage

    rgb = image if isinstance(image, np.ndarray) else _load_rgb(image)
    height = rgb.shape[0]
    top, bottom = np.array(BACKGROUND[0]), np.array(BACKGROUND[1])
    expected = top + (bottom - top) * (np.arange(height) / max(height - 1, 1))[:, None]
    mask = np.max(np.abs(rgb - expected[:, None, :]), axis=2) > DRAWN_THRESHOLD
    for left, upper, right, lower in exclude:
        mask[upper:lower, left:right] = False
    return np.asarray(ndimage.binary_opening(mask, structure=np.ones((OPENING, OPENING))), dtype=bool)


def drawn_box(image: str | Path | np.ndarray) -> tuple[int, int, int, int] | None:
    """Bounding box (left, top, right, bottom) [px] of :func:`drawn_mask`, or None when nothing is drawn."""
    mask = drawn_mask(image)
    rows, columns = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    if rows.size == 0:
        return None
    return int(columns[0]), int(rows[0]), int(columns[-1]) + 1, int(rows[-1]) + 1


@dataclasses.dataclass
class Census:
    """Pixels of each colour of interest on a screenshot (outside the legend and controls)."""

    arm: int
    spring: int
    total: int

    def ok(self, minimum_arm: int = 150, minimum_spring: int = 80) -> bool:
        return self.arm >= minimum_arm and self.spring >= minimum_spring

    def __str__(self) -> str:
        return f"arm-coloured pixels {self.arm}, spring-coloured pixels {self.spring} (of {self.total})"


def hue_mask(
    rgb: np.ndarray,
    reference: Sequence[float],
    hue_tolerance: float = 14.0,
    min_saturation: float = 0.35,
    min_value: float = 0.2,
) -> np.ndarray:
    """Pixels (H×W×3 in [0, 1]) whose hue is within ``hue_tolerance`` degrees of ``reference``'s,
    saturated and bright enough to be a lit surface of that colour rather than background."""
    maximum, minimum = rgb.max(axis=2), rgb.min(axis=2)
    chroma = maximum - minimum
    saturation = np.where(maximum > 0, chroma / np.maximum(maximum, 1e-9), 0.0)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    safe = np.maximum(chroma, 1e-9)
    hue = np.where(maximum == r, ((g - b) / safe) % 6, np.where(maximum == g, (b - r) / safe + 2, (r - g) / safe + 4))
    hue = 60.0 * hue
    target = 360.0 * colorsys.rgb_to_hsv(*reference)[0]
    distance = np.abs((hue - target + 180.0) % 360.0 - 180.0)
    return (distance <= hue_tolerance) & (saturation >= min_saturation) & (maximum >= min_value) & (chroma > 0.05)


def colour_census(
    image: str | Path,
    arm_colours: Iterable[Sequence[float]] | None,
    spring_colours: Iterable[Sequence[float]],
    exclude: Iterable[tuple[int, int, int, int]] = (LEGEND_BOX, CONTROLS_BOX, REGIONS_BOX, POSES_BOX),
) -> Census:
    """Count pixels of the arm's and the springs' colours on ``image``.

    ``arm_colours`` and ``spring_colours`` are RGB triples in [0, 1] (several allowed:
    a spring's colour changes with its tension); with ``arm_colours`` None the arm's pixels are the
    drawn ones (:func:`drawn_mask`) that are not of a spring's colour, whatever the arm's colours.
    Boxes in ``exclude`` (left, top, right, bottom) [px] are not counted.
    """
    rgb = _load_rgb(image)
    keep = np.ones(rgb.shape[:2], dtype=bool)
    for left, top, right, bottom in exclude:
        keep[top:bottom, left:right] = False

    def count(colours: Iterable[Sequence[float]]) -> int:
        mask = np.zeros(rgb.shape[:2], dtype=bool)
        for colour in colours:
            mask |= hue_mask(rgb, colour)
        return int(np.count_nonzero(mask & keep))

    spring_colours = list(spring_colours)
    if arm_colours is None:
        springs = np.zeros(rgb.shape[:2], dtype=bool)
        for colour in spring_colours:
            springs |= hue_mask(rgb, colour)
        arm = int(np.count_nonzero(drawn_mask(rgb, exclude) & ~springs & keep))
    else:
        arm = count(arm_colours)
    return Census(arm=arm, spring=count(spring_colours), total=int(np.count_nonzero(keep)))


def scale_colours(count: int = 41) -> list[tuple[float, float, float]]:
    """Colours of the whole tension scale, compression included (what a spring can look like)."""
    scale = ColorScale(1.0)
    return [scale.rgb(value) for value in np.linspace(-1.0, 1.0, count)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m springbalance.viz.browser",
        description="Render a scene.html in headless Chromium and check the arm and the springs are on the screenshot.",
    )
    parser.add_argument("page", help="scene.html written by 'springbalance report'")
    parser.add_argument("--screenshot", default=None, help="where to save the PNG (default: next to the page)")
    parser.add_argument(
        "--arm-colour",
        default=None,
        help="RGB in [0, 1] of the arm's material (default: any solid drawn pixel not of a spring's colour)",
    )
    args = parser.parse_args(argv)
    page = Path(args.page)
    image = Path(args.screenshot) if args.screenshot else page.with_suffix(".png")
    if find_chromium() is None:
        print(
            "demo-check: SKIPPED: Chromium is not installed (run `make chromium` as root, or install the "
            "Debian package `chromium`)"
        )
        return 77
    try:
        screenshot(page, image)
    except BrowserError as error:
        print(f"demo-check: FAILED: {error}")
        return 1
    arm = [tuple(float(v) for v in args.arm_colour.split(","))] if args.arm_colour else None
    springs = scale_colours()
    census = colour_census(image, arm, springs)
    verdict = "PASSED" if census.ok() else "FAILED"
    box = drawn_box(image)
    fill = (
        "nothing drawn"
        if box is None
        else f"drawn box {box[2] - box[0]}×{box[3] - box[1]} px of {WINDOW[0]}×{WINDOW[1]}"
    )
    print(f"demo-check: {verdict}: {page} rendered by {find_chromium()} into {image}: {census}; {fill}")
    return 0 if census.ok() else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
