"""Find URDFs shipped by the ``example-robot-data`` package.

example-robot-data 6.x on PyPI installs its robots under
``<site-packages>/cmeel.prefix/share/example-robot-data/robots/``; it has no Python
module. A robot is named by the stem of its URDF file (``ur5_robot``, ``panda``) or by
one of the short aliases the upstream loaders use (``ur5``, ``panda``, ``talos_arm``).
"""

from __future__ import annotations

import difflib
import functools
import sysconfig
from pathlib import Path

from springbalance.errors import InputError, SpringBalanceError

#: Short names used by example-robot-data's own loaders -> path below ``robots/``.
ALIASES: dict[str, str] = {
    "ur3": "ur_description/urdf/ur3_robot.urdf",
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "ur10": "ur_description/urdf/ur10_robot.urdf",
    "ur3_limited": "ur_description/urdf/ur3_joint_limited_robot.urdf",
    "ur5_limited": "ur_description/urdf/ur5_joint_limited_robot.urdf",
    "ur10_limited": "ur_description/urdf/ur10_joint_limited_robot.urdf",
    "panda": "panda_description/urdf/panda.urdf",
    "kinova": "kinova_description/robots/kinova.urdf",
    "z1": "z1_description/urdf/z1.urdf",
    "xarm7": "xarm_description/urdf/xarm7.urdf",
    "so100": "so_arm_description/urdf/so100.urdf",
    "so101": "so_arm_description/urdf/so101.urdf",
    "double_pendulum": "double_pendulum_description/urdf/double_pendulum.urdf",
    "double_pendulum_continuous": "double_pendulum_description/urdf/double_pendulum_continuous.urdf",
    "double_pendulum_simple": "double_pendulum_description/urdf/double_pendulum_simple.urdf",
    "talos_arm": "talos_data/robots/talos_left_arm.urdf",
    "finger_edu": "finger_edu_description/robots/finger_edu.urdf",
    "asr_twodof": "asr_twodof_description/urdf/TwoDofs.urdf",
}


@functools.lru_cache(maxsize=1)
def share_directory() -> Path:
    """The installed ``example-robot-data`` share folder (parent of ``robots/``)."""
    candidates = []
    for key in ("purelib", "platlib", "data"):
        base = Path(sysconfig.get_paths()[key])
        candidates += [base / "cmeel.prefix/share/example-robot-data", base / "share/example-robot-data"]
    for candidate in candidates:
        if (candidate / "robots").is_dir():
            return candidate
    raise InputError(
        "example-robot-data is not installed (looked in "
        + ", ".join(str(c) for c in candidates)
        + "); install it with `pip install example-robot-data`"
    )


@functools.lru_cache(maxsize=1)
def available_robots() -> dict[str, Path]:
    """Every robot name that :func:`robot_urdf` accepts, mapped to its URDF path."""
    robots_dir = share_directory() / "robots"
    names: dict[str, Path] = {}
    for urdf in sorted(robots_dir.rglob("*.urdf")):
        names.setdefault(urdf.stem, urdf)
    for alias, relative in ALIASES.items():
        if (robots_dir / relative).is_file():
            names[alias] = robots_dir / relative
    return dict(sorted(names.items()))


def robot_urdf(name: str) -> Path:
    """Path of the URDF of the example-robot-data robot ``name``.

    Raises:
        InputError: ``name`` is unknown; the message suggests up to three close names
            ("did you mean 'ur5'?") and points to ``springbalance robots`` for the full list.
    """
    robots = available_robots()
    if name not in robots:
        raise InputError(f"unknown example-robot-data robot {name!r}; {_suggestion(name, list(robots))}")
    return robots[name]


def _suggestion(name: str, names: list[str]) -> str:
    """``did you mean 'a', 'b' or 'c'?`` (close names, case-insensitive) plus where the full list is."""
    by_lower: dict[str, str] = {}
    for candidate in names:
        by_lower.setdefault(candidate.lower(), candidate)
    matches = [by_lower[match] for match in difflib.get_close_matches(str(name).lower(), list(by_lower), n=3)]
    hint = f"run `springbalance robots` for the full list of {len(names)}"
    if not matches:
        return hint
    quoted = [repr(match) for match in matches]
    alternatives = quoted[0] if len(quoted) == 1 else f"{', '.join(quoted[:-1])} or {quoted[-1]}"
    return f"did you mean {alternatives}? ({hint})"


def package_directories() -> list[str]:
    """Folders that resolve ``package://`` mesh paths of example-robot-data URDFs."""
    share = share_directory()
    return [str(share / "robots"), str(share.parent)]


def mesh_directories(source: dict) -> list[str]:
    """Folders where the meshes of a mechanism's URDF may be found (``Mechanism.source``): the URDF's
    folder and three above it, then example-robot-data's (when it is installed)."""
    directories = []
    if source.get("kind") in ("urdf", "robot"):
        path = Path(source["path"])
        directories += [str(folder) for folder in [path.parent, *list(path.parents)[1:4]]]
    try:
        directories += package_directories()
    except SpringBalanceError:
        pass
    return directories
