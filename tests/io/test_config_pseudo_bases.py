"""Pseudo-bases in a config (``mechanism.pseudo_bases``, issue 29): the example reaches exact balance with free
anchors, and bad entries are named by their key path."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from springbalance.errors import ConfigError
from springbalance.io.config import config_from_dict, load_config

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "pseudo_base_arm.yaml"


def test_free_anchors_reach_exact_balance():
    """Five zero-free-length springs pb_k → link_k, anchors free in ±0.2 m boxes, stiffnesses free: the solve finds
    an exact balance from the better of two starts (tests/model/test_pseudo_bases.py builds one inside these boxes by hand)."""
    config = load_config(EXAMPLE)
    assert [base.body for base in config.mechanism.pseudo_bases] == ["pb_a2", "pb_a3", "pb_a4", "pb_a5", "pb_a6"]
    result = config.solve(verify="off", progress=False)  # the example's 2 starts, seed 0
    unbalanced = np.max(np.abs(result.problem.workspace.kinematics().gravity_torque))
    assert unbalanced > 50
    assert np.max(np.abs(result.residual_torque())) <= 1e-9 * unbalanced
    assert result.exact_balance()["exact"]


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ("a9", "pseudo_bases[0].joint: unknown joint 'a9'"),
        ({"joint": "a2", "mass": -0.5}, "mechanism.pseudo_bases[0].mass"),
        ({"joint": "a2", "colour": 1}, "mechanism.pseudo_bases[0]: unknown key 'colour'"),
        ({"joint": "a2", "keep": "level"}, "mechanism.pseudo_bases[0].keep: unknown keep 'level'"),
    ],
)
def test_bad_pseudo_base_entries_are_named(entry, message):
    record = yaml.safe_load(EXAMPLE.read_text())
    record["mechanism"]["pseudo_bases"] = [entry]
    record["springs"] = record["springs"][:1]
    record["springs"][0]["a"]["body"] = "universe"
    with pytest.raises(ConfigError) as error:
        config_from_dict(record, base_dir=EXAMPLE.parent, label="arm.yaml")
    text = str(error.value)
    assert text.startswith("arm.yaml: mechanism") and message in text and "\n" not in text
