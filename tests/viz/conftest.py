"""Fixtures of the scene tests: the two-link design of :mod:`scene_helpers` and its saved file."""

from __future__ import annotations

import pytest

from scene_helpers import two_link_design


@pytest.fixture(scope="module")
def design():
    return two_link_design()


@pytest.fixture(scope="module")
def design_file(design, tmp_path_factory):
    return design.save(tmp_path_factory.mktemp("design") / "design.json")
