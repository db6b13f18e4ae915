"""``python -m springbalance``: the same command as ``springbalance``."""

import sys

from springbalance.cli import main

if __name__ == "__main__":
    sys.exit(main())
