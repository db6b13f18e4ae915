"""Settings of the whole test session.

- The compiled residuals go to a temporary cache folder (``SPRINGBALANCE_CACHE_DIR``), removed at
  the end: tests neither read nor fill the user's cache. Within the session, a problem met twice
  is compiled once. Subprocesses (the CLI tests) inherit the variable.
- ``make test`` spreads the test files over the cores (pytest-xdist, ``-n auto --maxprocesses 4 --dist loadfile``): the
  main process makes the folder, its workers (started with its environment) share it, and the main
  process removes it. The library writes it atomically (:mod:`springbalance.design.compile_cache`). The longest
  files run first (:data:`LONGEST_FIRST`), so that none is left to one worker at the end.
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


#: the files that take longest (each about a minute or more on two cores), run first: with the files spread over the
#: workers, one of them left to the end would keep one worker busy after the others finish
LONGEST_FIRST = ("test_examples_real.py", "test_explore.py", "test_notebooks.py", "test_robust_tolerance.py")


def pytest_collection_modifyitems(session, config, items):
    rank = {name: index for index, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))  # stable: the rest keep their order


def pytest_sessionfinish(session, exitstatus):
    if _OWNER:
        shutil.rmtree(_CACHE, ignore_errors=True)
