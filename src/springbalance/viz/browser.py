"""Open a static scene page in headless Chromium and check what is on the screenshot.

This is how the tests (and ``make demo-check``) make sure that ``scene.html`` really
renders — WebGL included — with no server and no network: Chromium loads the file, runs
for a few seconds of virtual time, and saves a PNG; :func:`colour_census` then counts the
pixels whose hue is that of the arm and of the springs.

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
import os
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
#: up to 8 joints and springs in all); not counted.
POSES_BOX = (WINDOW[0] - 400, WINDOW[1] - 190, WINDOW[0], WINDOW[1])


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
    chromium: str, page: Path, image: Path, profile: Path, window: tuple[int, int] = WINDOW, budget_ms: int = 2500
) -> list[str]:
    """The command line that renders ``page`` into ``image`` (software WebGL, nothing online)."""
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
        f"--screenshot={image}",
        f"--window-size={window[0]},{window[1]}",
        f"--virtual-time-budget={int(budget_ms)}",
        Path(page).resolve().as_uri(),
    ]


def screenshot(
    page: str | Path, image: str | Path, window: tuple[int, int] = WINDOW, budget_ms: int = 2500, timeout: float = 120.0
) -> Path:
    """Render ``page`` in headless Chromium and save a PNG screenshot to ``image``.

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
        command = chromium_command(chromium, Path(page), image, Path(profile), window, budget_ms)
        try:
            completed = subprocess.run(command, stdin=subprocess.DEVNULL, capture_output=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise BrowserError(f"Chromium took more than {timeout:g} s to render {page}") from None
    if not image.is_file() or image.stat().st_size == 0:
        tail = completed.stderr.decode("utf-8", "replace").strip().splitlines()[-3:]
        raise BrowserError(f"Chromium wrote no screenshot (exit {completed.returncode}): {' | '.join(tail)}")
    return image


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
    arm_colours: Iterable[Sequence[float]],
    spring_colours: Iterable[Sequence[float]],
    exclude: Iterable[tuple[int, int, int, int]] = (LEGEND_BOX, CONTROLS_BOX, POSES_BOX),
) -> Census:
    """Count pixels of the arm's and the springs' colours on ``image``.

    ``arm_colours`` and ``spring_colours`` are RGB triples in [0, 1] (several allowed:
    a spring's colour changes with its tension). Boxes in ``exclude`` (left, top, right,
    bottom) [px] are not counted.
    """
    from PIL import Image

    with Image.open(image) as picture:
        rgb = np.asarray(picture.convert("RGB"), dtype=float) / 255.0
    keep = np.ones(rgb.shape[:2], dtype=bool)
    for left, top, right, bottom in exclude:
        keep[top:bottom, left:right] = False

    def count(colours: Iterable[Sequence[float]]) -> int:
        mask = np.zeros(rgb.shape[:2], dtype=bool)
        for colour in colours:
            mask |= hue_mask(rgb, colour)
        return int(np.count_nonzero(mask & keep))

    return Census(arm=count(arm_colours), spring=count(spring_colours), total=int(np.count_nonzero(keep)))


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
        default="0.2,0.3,0.8",
        help="RGB in [0, 1] of the arm's material (default: link1 of urdf/two_link_planar.urdf)",
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
    arm = [tuple(float(v) for v in args.arm_colour.split(","))]
    springs = scale_colours()
    census = colour_census(image, arm, springs)
    verdict = "PASSED" if census.ok() else "FAILED"
    print(f"demo-check: {verdict}: {page} rendered by {find_chromium()} into {image}: {census}")
    return 0 if census.ok() else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
