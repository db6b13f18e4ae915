"""Compiled per-sample functions, cached on disk and shared between processes.

:func:`compile_function` turns a CasADi function into C (``CodeGenerator``), compiles it into a
shared library and loads it back with ``casadi.external``. The library is kept in a cache
folder under a key that hashes the generated C, the compiler (its resolved path, size and
modification time), the flags, the CasADi version and, with ``-march=native``, the processor's
instruction-set flags. A second process on the same problem finds the library and skips the
compiler; a process that meets the same function twice loads it once.

Where:
    ``$SPRINGBALANCE_CACHE_DIR/compiled`` when that variable is set, else
    ``platformdirs.user_cache_dir("springbalance")/compiled`` (``~/.cache/springbalance`` on
    Linux). The folder may be deleted at any time; it keeps the :data:`MAX_ENTRIES` most recently
    used libraries.

Flags:
    ``-O3 -march=native -ffp-contract=off``: vector instructions of this processor, but no fused
    multiply-adds, so that the results are bit for bit those of a plain ``-O2`` build (designs do
    not depend on the machine's instruction set). When the compiler refuses them, ``-O3``.
    ``SPRINGBALANCE_CFLAGS`` (space separated) replaces them.

Safety:
    the C file and the library are written under temporary names in the cache folder and the
    library is renamed into place (``os.replace``, atomic), so processes compiling the same key
    at once each produce a complete library and the last rename wins; a process never sees a
    half-written file.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from typing import Callable, TypeVar, cast

import casadi as ca

CACHE_ENV = "SPRINGBALANCE_CACHE_DIR"
FLAGS_ENV = "SPRINGBALANCE_CFLAGS"
FLAGS = ("-O3", "-march=native", "-ffp-contract=off")
FALLBACK_FLAGS = ("-O3",)
#: libraries kept in the cache folder (the least recently used beyond this are removed)
MAX_ENTRIES = 256
_SUFFIX = ".dll" if os.name == "nt" else ".so"


@dataclasses.dataclass
class CacheStats:
    """What this process did: libraries found in the cache (``hits``), compiled (``compiles``),
    and the seconds spent in the compiler."""

    hits: int = 0
    compiles: int = 0
    compile_seconds: float = 0.0


#: counters of this process (read by benchmarks/bench_startup.py and the tests)
STATS = CacheStats()
_loaded: dict[str, object] = {}  # key -> what load_or_build loaded (None: unusable)
#: what a loader of :func:`load_or_build` makes of a library
Loaded = TypeVar("Loaded")


def cache_dir() -> str:
    """The folder of compiled libraries (see the module docstring)."""
    folder = os.environ.get(CACHE_ENV)
    if not folder:
        import platformdirs

        folder = platformdirs.user_cache_dir("springbalance", appauthor=False)
    return os.path.join(folder, "compiled")


def compiler() -> str | None:
    """The C compiler: ``$CC`` (default ``gcc``), else ``cc``; None when neither is on PATH."""
    for name in (os.environ.get("CC", "gcc"), "cc"):
        path = shutil.which(name)
        if path:
            return path
    return None


def _flag_candidates() -> list[tuple[str, ...]]:
    custom = os.environ.get(FLAGS_ENV)
    if custom is not None:
        return [tuple(custom.split())]
    return [FLAGS, FALLBACK_FLAGS]


@functools.lru_cache(maxsize=8)
def _compiler_identity(path: str) -> str:
    real = os.path.realpath(path)
    try:
        info = os.stat(real)
        return f"{real}:{info.st_size}:{info.st_mtime_ns}"
    except OSError:
        return real


@functools.lru_cache(maxsize=1)
def _machine_identity() -> str:
    """The processor's instruction sets (what ``-march=native`` compiles for)."""
    identity = f"{platform.system()}-{platform.machine()}-{platform.processor()}"
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as cpuinfo:
            for line in cpuinfo:
                if line.startswith(("flags", "Features", "model name")):
                    identity += "|" + line.split(":", 1)[-1].strip()
                if line.strip() == "":  # the first processor is enough
                    break
    except OSError:
        pass
    return hashlib.sha256(identity.encode()).hexdigest()[:16]


def cache_key(code: str, compiler_path: str, flags: tuple[str, ...]) -> str:
    """The key of a library: a hash of the C code, the compiler, the flags and the platform."""
    # casadi's stubs do not declare the module's __version__ (it is set at import)
    version = ca.__version__  # type: ignore[attr-defined]
    parts = [
        code,
        _compiler_identity(compiler_path),
        " ".join(flags),
        version,
        sys.platform,
        _machine_identity() if any(flag.startswith(("-march", "-mcpu", "-mtune")) for flag in flags) else "",
    ]
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()[:40]


def generate_c(function: ca.Function) -> str:
    """The C code of ``function`` (CasADi's code generator)."""
    generator = ca.CodeGenerator(f"{function.name()}.c", {"with_header": False})
    generator.add(function)
    return generator.dump()


def compile_function(function: ca.Function) -> ca.Function:
    """``function`` as compiled C, from the disk cache when it holds it (else compiled and stored).

    Raises:
        RuntimeError: no compiler, or none of the flags compile the code.
    """

    def load(library: str) -> ca.Function | None:
        try:
            return ca.external(function.name(), library)
        except RuntimeError:  # not a usable library (a foreign file): built again
            return None

    loaded = load_or_build(generate_c(function), function.name(), load)
    if loaded is None:
        raise RuntimeError(f"could not load the compiled per-sample function {function.name()!r}")
    return loaded


def load_or_build(code: str, name: str, load: Callable[[str], Loaded | None]) -> Loaded | None:
    """What ``load(library)`` makes of the shared library compiled from the C ``code`` (the file
    ``<name>-<key>`` of the cache folder): from the cache when it holds a library ``load`` can use
    (``load`` returns None for one it cannot, which is then built again), else compiled and stored.
    The result is kept for the process under the key, None included.

    Raises:
        RuntimeError: no compiler, or none of the flags compile the code.
    """
    path = compiler()
    if path is None:
        raise RuntimeError("no C compiler on PATH")
    errors = []
    for flags in _flag_candidates():
        key = cache_key(code, path, flags)
        if key in _loaded:  # loaded by this loader: the key hashes the code it was given with
            return cast("Loaded | None", _loaded[key])
        folder = cache_dir()
        library = os.path.join(folder, f"{name}-{key}{_SUFFIX}")
        loaded = load(library) if os.path.exists(library) else None
        if loaded is not None:
            STATS.hits += 1
            _touch(library)
        else:
            try:
                _build(code, path, flags, folder, library)
            except (OSError, subprocess.SubprocessError) as error:
                errors.append(f"{' '.join(flags)}: {error}")
                continue
            loaded = load(library)
        _loaded[key] = loaded
        return loaded
    raise RuntimeError(f"could not compile {name}: " + "; ".join(errors))


def _build(code: str, compiler_path: str, flags: tuple[str, ...], folder: str, library: str) -> None:
    """Compile ``code`` into ``library``: written under temporary names, then renamed into place."""
    os.makedirs(folder, exist_ok=True)
    clock = time.perf_counter()
    source_fd, source = tempfile.mkstemp(prefix="tmp-", suffix=".c", dir=folder)
    target_fd, target = tempfile.mkstemp(prefix="tmp-", suffix=_SUFFIX, dir=folder)
    os.close(target_fd)
    try:
        with os.fdopen(source_fd, "w", encoding="utf-8") as handle:
            handle.write(code)
        command = [compiler_path, "-shared", "-fPIC", *flags, source, "-o", target]
        if os.name != "nt":
            command.append("-lm")
        run = subprocess.run(command, capture_output=True, text=True)
        if run.returncode != 0:
            raise subprocess.SubprocessError(
                run.stderr.strip().splitlines()[-1] if run.stderr.strip() else f"exit status {run.returncode}"
            )
        os.chmod(target, 0o644)
        os.replace(target, library)
    finally:
        for leftover in (source, target):
            try:
                os.remove(leftover)
            except OSError:
                pass
    STATS.compiles += 1
    STATS.compile_seconds += time.perf_counter() - clock
    _prune(folder)


def _touch(path: str) -> None:
    try:
        os.utime(path)
    except OSError:
        pass


def _prune(folder: str) -> None:
    """Keep the :data:`MAX_ENTRIES` most recently used libraries; drop temporary files a crashed
    process left behind (older than a day)."""
    try:
        entries = [entry for entry in os.scandir(folder) if entry.is_file()]
    except OSError:
        return
    now = time.time()
    libraries = []
    for entry in entries:
        try:
            modified = entry.stat().st_mtime
        except OSError:
            continue
        if entry.name.startswith("tmp-"):
            if now - modified > 86400:
                _remove(entry.path)
        elif entry.name.endswith(_SUFFIX):
            libraries.append((modified, entry.path))
    for _, path in sorted(libraries, reverse=True)[MAX_ENTRIES:]:
        _remove(path)


def _remove(path: str) -> None:
    try:
        os.remove(path)
    except OSError:
        pass
