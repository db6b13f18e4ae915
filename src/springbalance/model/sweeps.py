"""Ordered paths through a design's workspace, for plots and animations.

A *sweep* of joint ``j`` moves that joint from the lowest to the highest value it takes in
the design's workspace while every other joint stays at the middle of its own workspace
range (the range of the samples, not the URDF limits). The torque plots use one sweep per
joint; the Meshcat animation strings the sweeps together into one closed path
(middle → upper → lower → middle for each joint in turn), so the arm never jumps.

Joint coordinates are in rad (revolute, continuous) or m (prismatic).
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from springbalance.model.mechanism import Joint, Mechanism
from springbalance.model.workspace import Workspace


class _Problem(Protocol):
    @property
    def mechanism(self) -> Mechanism:
        """The arm."""

    @property
    def workspace(self) -> Workspace:
        """The design's workspace samples."""


class Designed(Protocol):
    """A design on its problem (a design result): what the sweeps read is ``problem.mechanism`` and
    ``problem.workspace`` (read-only)."""

    @property
    def problem(self) -> _Problem:
        """The design problem."""


def workspace_ranges(result: Designed) -> tuple[np.ndarray, np.ndarray]:
    """Lowest and highest value of every joint over the design's workspace samples (nv each)."""
    values = result.problem.workspace.joint_values
    return values.min(axis=0), values.max(axis=0)


def moving_joints(result: Designed) -> list[Joint]:
    """The joints whose workspace range has a non-zero width (a held joint is not swept)."""
    lower, upper = workspace_ranges(result)
    return [joint for joint in result.problem.mechanism.joints if upper[joint.index_v] > lower[joint.index_v]]


def joint_sweep(result: Designed, joint: str, n: int = 121) -> Workspace:
    """Ordered sweep of ``joint`` over its workspace range, the others at their range middles."""
    mechanism = result.problem.mechanism
    lower, upper = workspace_ranges(result)
    ranges = {other.name: [lower[other.index_v], upper[other.index_v]] for other in mechanism.joints}
    return Workspace.sweep(mechanism, joint, n=n, ranges=ranges)


def animation_path(result: Designed, frames_per_joint: int = 48) -> np.ndarray:
    """Joint values (N×nv) of a closed path that sweeps each moving joint in turn.

    Each joint goes middle → upper → lower → middle of its workspace range in
    ``frames_per_joint`` steps; the path starts and ends at the middle configuration.
    A design whose workspace is a single pose gives that one pose.
    """
    lower, upper = workspace_ranges(result)
    middle = (lower + upper) / 2
    rows = [middle]
    quarter = max(int(frames_per_joint) // 4, 1)
    for joint in moving_joints(result):
        j = joint.index_v
        legs = [
            np.linspace(middle[j], upper[j], quarter + 1)[1:],
            np.linspace(upper[j], lower[j], 2 * quarter + 1)[1:],
            np.linspace(lower[j], middle[j], quarter + 1)[1:],
        ]
        for value in np.concatenate(legs):
            row = middle.copy()
            row[j] = value
            rows.append(row)
    return np.array(rows)
