"""The viz package's layout: meshcat imported on first use only, the names of the old scene module
still importable from it, and the deprecated alias of a scene's design."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import springbalance as sb
from scene_helpers import two_link_design
from springbalance.errors import SpringBalanceError
from springbalance.viz import meshcat_import
from springbalance.viz import scene as viz

VIZ_MODULES = (
    "arm",
    "arm_meshes",
    "browser",
    "camera",
    "colors",
    "design_scene",
    "helix",
    "live",
    "meshcat_glue",
    "meshcat_import",
    "overlay",
    "recorder",
    "regions",
    "scene",
    "server",
    "tracks",
)


def test_importing_the_viz_modules_does_not_import_meshcat():
    imports = "; ".join(f"import springbalance.viz.{name}" for name in VIZ_MODULES)
    code = f"import sys; {imports}; print(sorted(m for m in sys.modules if m.split('.')[0] == 'meshcat'))"
    completed = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert completed.stdout.strip() == "[]"


def test_a_missing_meshcat_is_a_clear_error(monkeypatch):
    meshcat_import.import_meshcat.cache_clear()
    monkeypatch.setitem(sys.modules, "meshcat", None)  # `import meshcat` raises ImportError
    try:
        with pytest.raises(SpringBalanceError, match="needs meshcat.*pip install meshcat"):
            meshcat_import.import_meshcat()
    finally:
        meshcat_import.import_meshcat.cache_clear()


def test_the_old_names_of_the_scene_module_still_import():
    meshcat = meshcat_import.import_meshcat()
    assert viz.meshcat is meshcat and viz.mg is meshcat.geometry
    assert issubclass(viz._TextSprite, meshcat.geometry.Object)
    assert issubclass(viz._Animation, meshcat.animation.Animation)
    assert issubclass(viz._SetAnimation, meshcat.commands.SetAnimation)
    assert viz._SetAnimation(viz._Animation()).lower()["path"] == f"/{viz.ROOT}-animation"
    for name in (
        "DesignScene",
        "SpringTrack",
        "RegionShape",
        "StaticScene",
        "scene_html",
        "save_scene_html",
        "show",
        "camera_distance",
        "CAMERA_FOV",
        "LABEL_FONT_SIZE",
        "_region_geometry",
        "_insert_before_body_end",
        "_anchors",
        "_region_corners",
        "_region_points",
        "_box_mesh",
    ):
        assert hasattr(viz, name), name
    with pytest.raises(AttributeError):
        _ = viz.no_such_name


def test_scene_result_is_a_deprecated_alias_of_its_design():
    design = two_link_design(3)
    scene = viz.DesignScene(design, frames_per_joint=3)
    with pytest.warns(DeprecationWarning, match="DesignScene.design"):
        assert scene.result is design


def test_a_scene_needs_only_the_numbers_of_a_design():
    """viz is typed on EvaluatedDesign: a plain one (no DesignResult, nothing of springbalance.results)
    draws the same scene as the DesignResult of the same problem and design vector."""
    result = two_link_design(3)
    plain = sb.EvaluatedDesign(result.problem, result.x)
    assert not isinstance(plain, sb.DesignResult)
    scenes = [viz.DesignScene(design, frames_per_joint=3) for design in (plain, result)]
    for mine, theirs in zip(*(scene.springs for scene in scenes)):
        np.testing.assert_array_equal(mine.starts, theirs.starts)
        np.testing.assert_array_equal(mine.tensions, theirs.tensions)
    assert scenes[0].legend_html() == scenes[1].legend_html()
    assert viz.scene_html(plain, frames_per_joint=3, animate=False).lstrip().startswith("<!DOCTYPE html>")
