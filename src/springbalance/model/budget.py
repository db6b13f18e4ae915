"""Memory budgets: work whose arrays would not fit is refused before anything is allocated.

The constructors of workspaces, their kinematics, a design problem's evaluation and the CLI's
scenes estimate the memory [bytes] they will need from the sample count and the problem size,
and call :func:`require`, which raises :class:`~springbalance.errors.InputError` with the
estimate and the limit in the message when the estimate is above the limit. The estimates are
deliberately generous (they count the temporary copies too); they are to stop ``n: 1e8`` with
a clear message, not to squeeze the last sample into memory.

The limit [bytes], first found of:

1. the value given to :func:`memory_limit` (the command line's ``--max-memory``);
2. the environment variable ``SPRINGBALANCE_MAX_MEMORY``;
3. half the memory available to this process (:func:`available_memory`).

Sizes are written as a number of bytes with an optional binary unit: ``2G``, ``2GiB``,
``512M``, ``64k``, ``1.5e9``; ``unlimited`` (or ``none``) switches the check off.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import resource
from collections.abc import Iterator
from pathlib import Path

from springbalance.errors import InputError

#: environment variable that sets the limit (same syntax as ``--max-memory``)
ENV = "SPRINGBALANCE_MAX_MEMORY"
#: the default limit is this fraction of the memory available to the process
DEFAULT_FRACTION = 0.5

_UNITS = {"": 1, "b": 1, "k": 1 << 10, "m": 1 << 20, "g": 1 << 30, "t": 1 << 40, "p": 1 << 50}
_SIZE = re.compile(r"^\s*([0-9]+(?:\.[0-9]*)?(?:[eE][+-]?[0-9]+)?|\.[0-9]+)\s*([kKmMgGtTpP]?)(?:i?[bB])?\s*$")
_UNLIMITED = ("unlimited", "none", "off")

#: set by :func:`memory_limit`: ``(bytes or None for no limit, where it came from)``
_override: tuple[int | None, str] | None = None


# ---------------------------------------------------------------------- the limit
def parse_size(text: str | int | float, where: str = "memory size") -> int | None:
    """Bytes of a size such as ``2G``, ``512MiB``, ``1.5e9`` or ``65536``; None for ``unlimited``.

    Raises:
        InputError: not a size, or not a finite number > 0 (``where`` names the option).
    """
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        value = float(text)
        if not math.isfinite(value) or value <= 0:
            raise InputError(f"{where}: must be a finite number of bytes > 0, got {text!r}")
        return int(value)
    if not isinstance(text, str):
        raise InputError(f"{where}: expected a size such as 2G or 512M, got {text!r}")
    if text.strip().lower() in _UNLIMITED:
        return None
    match = _SIZE.match(text)
    if match is None:
        raise InputError(f"{where}: expected a size such as 2G, 512M, 1.5e9 (bytes) or 'unlimited', got {text!r}")
    value = float(match.group(1)) * _UNITS[match.group(2).lower()]
    if not math.isfinite(value) or value < 1:
        raise InputError(f"{where}: must be at least 1 byte, got {text!r}")
    return int(value)


@contextlib.contextmanager
def memory_limit(size: str | int | float | None, where: str = "--max-memory") -> Iterator[None]:
    """Within the block, the limit is ``size`` (see :func:`parse_size`; None leaves it as it is)."""
    global _override
    saved = _override
    if size is not None:
        _override = (parse_size(size, where), where)
    try:
        yield
    finally:
        _override = saved


def current_limit() -> tuple[int | None, str]:
    """``(limit [bytes] or None when unlimited, how it was set)``: see the module documentation."""
    if _override is not None:
        return _override
    text = os.environ.get(ENV)
    if text is not None and text.strip():
        return parse_size(text, f"environment variable {ENV}"), ENV
    available = available_memory()
    if available is None:
        return None, "no limit: the available memory is unknown"
    return int(available * DEFAULT_FRACTION), "half the available memory"


def available_memory() -> int | None:
    """Memory [bytes] this process may still allocate: the smallest of the machine's available
    memory (``MemAvailable``), the room left in its cgroup (``memory.max``) and the room left
    under its address-space and data limits (``ulimit -v``, ``ulimit -d``). None when none is known."""
    candidates = []
    meminfo = _meminfo()
    if "MemAvailable" in meminfo:
        candidates.append(meminfo["MemAvailable"])
    else:
        with contextlib.suppress(ValueError, OSError, AttributeError):
            candidates.append(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    cgroup = _cgroup_room()
    if cgroup is not None:
        candidates.append(cgroup)
    status = _self_status()
    for limit_kind, used_key in ((resource.RLIMIT_AS, "VmSize"), (getattr(resource, "RLIMIT_DATA", None), "VmData")):
        if limit_kind is None:
            continue
        with contextlib.suppress(ValueError, OSError):
            soft, _ = resource.getrlimit(limit_kind)
            if soft != resource.RLIM_INFINITY and soft > 0:
                candidates.append(max(soft - status.get(used_key, 0), 0))
    return min(candidates) if candidates else None


def require(nbytes: float, what: str) -> None:
    """Raise :class:`InputError` when ``nbytes`` (an estimate) is above the limit.

    ``what`` says what needs the memory, e.g. ``"a sobol workspace of 100000000 samples of 2
    joints"``; the message gives the estimate, the limit and how to change it.
    """
    limit, source = current_limit()
    if limit is None or nbytes <= limit:
        return
    if source.startswith("--") or source == ENV:
        change = f"raise {source}"
    else:
        change = f"raise the limit with --max-memory SIZE or the environment variable {ENV}"
    raise InputError(
        f"{what} would need about {format_bytes(nbytes)} of memory (estimate), more than the limit of "
        f"{format_bytes(limit)} ({source}); ask for less, or {change}"
    )


def format_bytes(nbytes: float) -> str:
    """``80000000000`` → ``74.5 GiB`` (binary units)."""
    if nbytes >= 1 << 1000:  # beyond a float
        return "more than 1e+280 EiB"
    value = float(nbytes)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(value) < 1024 or unit == "PiB":
            return f"{value:.0f} {unit}" if unit == "B" else f"{value:.3g} {unit}"
        value /= 1024
    return f"{value:.3g} EiB"  # pragma: no cover


# ---------------------------------------------------------------------- estimates [bytes]
FLOAT = 8  # bytes of a float64


def sampling_bytes(kind: str, n: int, nv: int) -> int:
    """Memory [bytes] to draw ``n`` samples of ``nv`` joints: ``kind`` is ``"sobol"`` (a power-of-two
    batch, the unit samples, the scaled ones and the accepted stack), ``"random"``, ``"grid"`` (``n``
    the number of grid points: the mesh arrays, their stack and the coupled copy) or ``"sweep"``."""
    n, nv = int(n), max(int(nv), 1)
    if kind == "sobol":
        batch = 1 << max(int(n - 1).bit_length(), 6)
        return FLOAT * batch * (4 * nv + 2)
    if kind == "random":
        return FLOAT * max(n, 64) * (4 * nv + 2)
    if kind == "grid":
        return FLOAT * n * (3 * nv + 2)
    return FLOAT * n * (2 * nv + 2)  # sweep, arrays


def kinematics_bytes(n: int, nv: int, nq: int) -> int:
    """Memory [bytes] of a workspace's gravity cache: configurations, gravity torques, potentials."""
    return FLOAT * int(n) * (3 * int(nq) + 4 * int(nv) + 5)


def evaluation_bytes(n: int, nv: int, nq: int, data_size: int, outputs: int, variables: int, rows: int) -> int:
    """Memory [bytes] of a design problem over ``n`` samples, solved: the gravity cache, the sample
    data (``data_size`` numbers per sample, held four times while it is laid out and mapped), the
    outputs of an evaluation (``outputs`` per sample, twice) and the solvers' Jacobians and their
    work space (``nv + rows`` residuals and constraint rows per sample, ``variables`` columns, eight
    times: measured on the UR5 with two springs, 100 000 samples, 1.1 GiB)."""
    per_sample = 4 * data_size + 2 * outputs + 8 * (nv + rows) * max(variables, 1)
    return kinematics_bytes(n, nv, nq) + FLOAT * int(n) * per_sample


#: memory [bytes] a 3-D scene takes per animation frame and drawn object (the arm's bodies, the springs):
#: the transforms and the scene's JSON/HTML text (measured: 2.7 KiB of scene.html each, held about five times)
SCENE_BYTES_PER_OBJECT_FRAME = 16 << 10


def scene_bytes(frames: int, objects: int) -> int:
    """Memory [bytes] of an animated scene of ``frames`` frames and ``objects`` drawn objects."""
    return SCENE_BYTES_PER_OBJECT_FRAME * int(frames) * max(int(objects), 1)


#: memory [bytes] per byte of a samples file read whole: a .npy array (the file and its float copy), a
#: .csv file (its text, its lines, a Python float per number and the array)
NPY_BYTES_PER_BYTE = 2
CSV_BYTES_PER_BYTE = 40


def file_bytes(path: str | Path) -> int:
    """Size of a file [bytes] (0 when it cannot be read: the reader then says why)."""
    try:
        return Path(path).stat().st_size
    except OSError:
        return 0


# ---------------------------------------------------------------------- the system's numbers
def _meminfo() -> dict[str, int]:
    try:
        text = Path("/proc/meminfo").read_text()
    except OSError:
        return {}
    values = {}
    for line in text.splitlines():
        key, _, rest = line.partition(":")
        parts = rest.split()
        if parts and parts[0].isdigit():
            values[key] = int(parts[0]) * (1024 if parts[1:] == ["kB"] else 1)
    return values


def _self_status() -> dict[str, int]:
    """``VmSize`` and ``VmData`` of this process [bytes] (empty where /proc is not there)."""
    try:
        text = Path("/proc/self/status").read_text()
    except OSError:
        return {}
    values = {}
    for line in text.splitlines():
        key, _, rest = line.partition(":")
        if key in ("VmSize", "VmData"):
            parts = rest.split()
            if parts and parts[0].isdigit():
                values[key] = int(parts[0]) * 1024
    return values


def _cgroup_room() -> int | None:
    """``memory.max - memory.current`` of this process's cgroup (v2) [bytes], or None."""
    try:
        line = Path("/proc/self/cgroup").read_text().splitlines()[0]
        folder = Path("/sys/fs/cgroup") / line.split("::", 1)[1].lstrip("/")
        maximum = (folder / "memory.max").read_text().strip()
        if maximum == "max":
            return None
        current = int((folder / "memory.current").read_text().strip())
        return max(int(maximum) - current, 0)
    except (OSError, IndexError, ValueError):
        return None
