"""``python -m springbalance``: the same command as ``springbalance``."""

from springbalance.cli import run

if __name__ == "__main__":
    run()
