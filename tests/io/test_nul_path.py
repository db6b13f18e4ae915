"""A file path with a NUL byte (no file can have that name) is a one-line input error naming the path and
the config key, not a ValueError traceback ("embedded null byte")."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from config_helpers import SHOULDER_SPRING
from springbalance import ConfigError, InputError
from springbalance.cli import main
from springbalance.io.config import config_from_dict
from springbalance.model.mechanism import Mechanism

NUL_URDF = "a\x00b.urdf"


def record(urdf: str = NUL_URDF) -> dict:
    return {"mechanism": {"urdf": urdf}, "workspace": {"n": 8}, "springs": [SHOULDER_SPRING]}


def test_from_urdf_names_the_path():
    with pytest.raises(InputError, match=r"URDF file 'a\\x00b.urdf' is not a valid path: it contains a NUL byte"):
        Mechanism.from_urdf(NUL_URDF)


def test_config_names_the_key_and_the_path(tmp_path):
    with pytest.raises(ConfigError) as caught:
        config_from_dict(record(), base_dir=tmp_path, label="c.yaml")
    message = str(caught.value)
    assert message.startswith("c.yaml: mechanism.urdf: URDF file ")
    assert "\\x00b.urdf" in message and "NUL byte" in message and "\n" not in message


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
def test_cli_design_exits_with_one_line(tmp_path, capsys, suffix):
    config = tmp_path / f"c{suffix}"
    # JSON text; YAML reads it too, the NUL byte written as the escape \u0000
    config.write_text(json.dumps(record()))
    assert "\\u0000" in config.read_text()
    out = tmp_path / "design.json"
    status = main(["design", str(config), "--out", str(out), "--starts", "1", "--quiet"])
    captured = capsys.readouterr()
    assert status != 0
    assert "Traceback" not in captured.err and "embedded null byte" not in captured.err
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and f"{config}: mechanism.urdf: URDF file " in lines[0] and "NUL byte" in lines[0]
    assert not Path(out).exists()
