"""Checks and loads shared by the commands: an output path that can be written, a saved design (on its own
workspace or another one), the memory of a 3-D scene."""

from __future__ import annotations

import os
from pathlib import Path

from springbalance.errors import InputError
from springbalance.io.config import load_workspace
from springbalance.model import budget
from springbalance.model.sweeps import moving_joints
from springbalance.results.result import DesignResult
from springbalance.viz.pose_paths import WORST_COUNT, parse_poses


def check_output(out: Path, option: str = "--out", example: str = "design.json") -> None:
    """Fail before solving (or exporting) when the file could not be saved at ``out``."""
    if out.is_dir():
        raise InputError(f"{option} {str(out)!r} is a directory; give a file name such as {example}")
    folder = out.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir():
        raise InputError(f"{option} {str(out)!r}: {str(folder)!r} is not a directory")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"{option} {str(out)!r}: folder {str(folder)!r} is not writable")


def load_result(design: str, workspace: str | None = None) -> DesignResult:
    """The design saved at ``design``, evaluated on its own workspace, or on the ``workspace:`` mapping of the
    YAML/JSON file ``workspace`` (``--workspace``)."""
    result = DesignResult.load(design)
    if workspace is not None:
        mechanism = result.problem.mechanism
        result = DesignResult.load(design, mechanism=mechanism, workspace=load_workspace(workspace, mechanism))
    return result


def check_scene_budget(result: DesignResult, frames_per_joint: int, poses: str = "sweep") -> None:
    """Refuse (--frames too large) a scene whose estimated memory is above the limit, before drawing it; ``poses``
    (``--poses``, :func:`springbalance.viz.pose_paths.parse_poses`) is checked first."""
    kind, count = parse_poses(poses)
    frames, why = (
        frames_per_joint * max(len(moving_joints(result)), 1) + 1,
        f"--frames {frames_per_joint} per moving joint",
    )
    if kind != "sweep":
        size = result.problem.workspace.size
        frames, why = (size if kind == "workspace" else min(count or WORST_COUNT, size)), f"--poses {poses}"
    objects = len(result.problem.mechanism.body_names) + len(result.problem.springs)
    budget.require(budget.scene_bytes(frames, objects), f"a scene of {frames} frames ({why}) and {objects} objects")
