"""Settings of the whole test session.

- The compiled residuals go to a temporary cache folder (``SPRINGBALANCE_CACHE_DIR``), removed at
  the end: tests neither read nor fill the user's cache. Within the session, a problem met twice
  is compiled once. Subprocesses (the CLI tests) inherit the variable.
- Solves run their starts in this process (``SPRINGBALANCE_WORKERS=1``): the test problems are
  small, and a pool's start-up would cost more than it saves. Tests of the pool pass ``workers``.
"""

from __future__ import annotations

import os
import shutil
import tempfile

_CACHE = tempfile.mkdtemp(prefix="springbalance-test-cache-")
os.environ["SPRINGBALANCE_CACHE_DIR"] = _CACHE
os.environ["SPRINGBALANCE_WORKERS"] = "1"


def pytest_sessionfinish(session, exitstatus):
    shutil.rmtree(_CACHE, ignore_errors=True)
