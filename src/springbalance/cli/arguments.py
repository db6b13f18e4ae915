"""Argument types of the command line: integers checked by argparse, so that a bad value is reported as
``springbalance COMMAND: error: argument --x: ...`` with the command's usage."""

from __future__ import annotations

import argparse

#: the help of ``--max-memory``, accepted before and after the command's name
MEMORY_HELP = (
    "refuse work estimated to need more memory than SIZE (e.g. 2G, 512M, or 'unlimited'; default: "
    "the environment variable SPRINGBALANCE_MAX_MEMORY, else half the available memory)"
)


def positive_int(text: str) -> int:
    """An integer ≥ 1."""
    value = nonnegative_int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be ≥ 1, got {text!r}")
    return value


def port(text: str) -> int:
    """A TCP port, 1 … 65535."""
    value = nonnegative_int(text)
    if not 1 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"a port is 1 … 65535, got {text!r}")
    return value


def nonnegative_int(text: str) -> int:
    """An integer ≥ 0."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be ≥ 0, got {text!r}")
    return value


#: most seeds ``--seeds`` takes (each is a whole solve)
MAX_SEEDS = 64


def seed_list(text: str) -> list[int]:
    """Distinct integers ≥ 0, as ``0-4`` (a range, both ends included) or ``0,3,7`` (a list), or both
    (``0-2,7``); at most :data:`MAX_SEEDS` of them."""
    seeds: list[int] = []
    for part in text.split(","):
        low, dash, high = part.strip().partition("-")
        first = nonnegative_int(low)
        last = nonnegative_int(high) if dash else first
        if last < first:
            raise argparse.ArgumentTypeError(f"a range of seeds goes up, got {part.strip()!r}")
        if last - first >= MAX_SEEDS:
            raise argparse.ArgumentTypeError(f"at most {MAX_SEEDS} seeds, got {part.strip()!r}")
        seeds.extend(range(first, last + 1))
    if len(set(seeds)) != len(seeds):
        raise argparse.ArgumentTypeError(f"seeds must be distinct, got {text!r}")
    if len(seeds) > MAX_SEEDS:
        raise argparse.ArgumentTypeError(f"at most {MAX_SEEDS} seeds, got {len(seeds)}")
    return seeds
