"""``python -m springbalance.cli``: the same command as ``springbalance``."""

from __future__ import annotations

from springbalance.cli.app import run

if __name__ == "__main__":
    run()
