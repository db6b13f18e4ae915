"""Settings of the whole test session.

- The compiled residuals go to a temporary cache folder (``SPRINGBALANCE_CACHE_DIR``), removed at
  the end: tests neither read nor fill the user's cache. Within the session, a problem met twice
  is compiled once. Subprocesses (the CLI tests) inherit the variable.
- ``make test`` spreads the test files over the cores (pytest-xdist, ``-n auto --maxprocesses 4 --dist loadfile``): the
  main process makes the folder, its workers (started with its environment) share it, and the main
  process removes it. The library writes it atomically (:mod:`springbalance.design.compile_cache`).
- Solves run their starts in this process (``SPRINGBALANCE_WORKERS=1``): the test problems are
  small, and a pool's start-up would cost more than it saves. Tests of the pool pass ``workers``.
"""

from __future__ import annotations

import os
import shutil
import tempfile

#: set by the process that made the cache folder, so that its xdist workers share the folder
_SHARED = "SPRINGBALANCE_TEST_CACHE"

if os.environ.get("PYTEST_XDIST_WORKER") and os.environ.get(_SHARED):
    _CACHE, _OWNER = os.environ[_SHARED], False  # an xdist worker: the main process's folder
else:
    _CACHE, _OWNER = tempfile.mkdtemp(prefix="springbalance-test-cache-"), True
    os.environ[_SHARED] = _CACHE
os.environ["SPRINGBALANCE_CACHE_DIR"] = _CACHE
os.environ["SPRINGBALANCE_WORKERS"] = "1"


def pytest_sessionfinish(session, exitstatus):
    if _OWNER:
        shutil.rmtree(_CACHE, ignore_errors=True)
