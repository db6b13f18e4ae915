"""Scrambled Sobol points without importing :mod:`scipy.stats` (half a second at start-up).

:class:`ScrambledSobol` gives, bit for bit, the points of
``scipy.stats.qmc.Sobol(d, scramble=True, seed=generator)`` drawn with ``random(n)``: the same
direction numbers (Joe and Kuo, read from SciPy's own data file), the same left linear matrix
scramble and digital shift drawn from the same child of the generator, and the same Gray-code
order. tests/model/test_sobol.py checks the equality against SciPy.

When SciPy's data file cannot be found (a SciPy that moved it), :func:`sobol_engine` falls back
to ``scipy.stats.qmc.Sobol`` itself.
"""

from __future__ import annotations

import functools
import os
from typing import TYPE_CHECKING, cast

import numpy as np

if TYPE_CHECKING:
    from scipy.stats import qmc

BITS = 30  # SciPy's default: points are multiples of 2**-30, stored as uint32


#: dimensions whose direction numbers are kept in memory after the first read (all 21,201 take 3 MB)
KEPT_DIMENSIONS = 1024


@functools.lru_cache(maxsize=2)
def _direction_numbers(dimensions: int = KEPT_DIMENSIONS) -> tuple[np.ndarray, np.ndarray] | None:
    """``(poly, vinit)`` of the first ``dimensions`` dimensions in SciPy's ``_sobol_direction_numbers.npz``
    (None when the file is missing)."""
    try:
        import scipy  # the package alone (9 ms), for its folder: not scipy.stats (half a second)
    except ImportError:
        return None
    for folder in scipy.__path__:
        path = os.path.join(folder, "stats", "_sobol_direction_numbers.npz")
        if os.path.exists(path):
            with np.load(path) as numbers:
                return numbers["poly"][:dimensions].copy(), numbers["vinit"][:dimensions].copy()
    return None


def _direction_matrix(d: int, poly: np.ndarray, vinit: np.ndarray) -> np.ndarray:
    """The d×BITS direction numbers ``v`` (Bratley and Fox's recurrence), column j scaled by 2^(BITS-1-j)."""
    v = np.zeros((d, BITS), dtype=np.uint64)
    if d == 0:
        return v
    v[0, :] = 1
    for row in range(1, d):
        p = int(poly[row])
        m = p.bit_length() - 1
        values = [int(x) for x in vinit[row, :m]]
        for j in range(m, BITS):
            new = values[j - m]
            for k in range(m):
                if (p >> (m - 1 - k)) & 1:
                    new ^= (2 << k) * values[j - k - 1]
            values.append(new)
        v[row, :] = values[:BITS]
    return v << np.arange(BITS - 1, -1, -1, dtype=np.uint64)[None, :]


class ScrambledSobol:
    """Scrambled (LMS + digital shift) Sobol points in [0, 1)^d, as ``scipy.stats.qmc.Sobol``.

    Args:
        d: dimension.
        rng: a :class:`numpy.random.Generator`; as SciPy does, the engine draws its scramble from a
            child spawned from the generator's seed sequence (the generator's own stream is not used).
    """

    def __init__(self, d: int, rng: np.random.Generator, numbers: tuple[np.ndarray, np.ndarray]):
        self.d = int(d)
        bit_generator = rng.bit_generator
        # numpy types seed_seq as ISeedSequence (no spawn); a Generator seeded as here holds a SeedSequence
        seed_seq = cast(np.random.SeedSequence, bit_generator.seed_seq)
        child = np.random.Generator(type(bit_generator)(seed_seq.spawn(1)[0]))
        poly, vinit = numbers
        v = _direction_matrix(self.d, poly, vinit)
        # digital shift, then the lower-triangular scramble matrices (unit diagonal), as SciPy draws them
        shift = child.integers(2, size=(self.d, BITS), dtype=np.uint32).astype(np.uint64)
        self._shift = (shift << np.arange(BITS, dtype=np.uint64)[None, :]).sum(axis=1).astype(np.uint64)
        ltm = np.tril(child.integers(2, size=(self.d, BITS, BITS), dtype=np.uint32)).astype(np.int64)
        ltm[:, np.arange(BITS), np.arange(BITS)] = 1
        # scrambled direction number: bits (most significant first) M @ bits(v) mod 2
        msb_first = np.arange(BITS - 1, -1, -1, dtype=np.uint64)
        bits = ((v[:, :, None] >> msb_first[None, None, :]) & np.uint64(1)).astype(np.int64)  # d × j × bit
        scrambled = np.einsum("dpc,djc->djp", ltm, bits) % 2
        self._v = (scrambled.astype(np.uint64) << msb_first[None, None, :]).sum(axis=2).astype(np.uint64)  # d × BITS
        self.num_generated = 0

    def random(self, n: int = 1) -> np.ndarray:
        """The next ``n`` points (n×d). Point k of the sequence is the shift XOR the direction numbers
        selected by the bits of the Gray code of k; point k+1 is point k XOR the direction number of
        the lowest zero bit of k."""
        n = int(n)
        start = self.num_generated
        if start + n > 1 << BITS:
            raise ValueError(f"at most 2**{BITS} Sobol points can be drawn")
        quasi = np.empty((n, self.d), dtype=np.uint64)
        if n:
            gray = start ^ (start >> 1)
            first = self._shift.copy()
            for bit in range(BITS):
                if (gray >> bit) & 1:
                    first ^= self._v[:, bit]
            quasi[0] = first
            if n > 1:
                k = np.arange(start, start + n - 1, dtype=np.int64)
                lowest_zero = np.frexp(((~k) & (k + 1)).astype(np.float64))[1] - 1  # position of k's lowest 0 bit
                quasi[1:] = self._v[:, lowest_zero].T
                np.bitwise_xor.accumulate(quasi, axis=0, out=quasi)
        self.num_generated += n
        return quasi.astype(np.float64) * (1.0 / (1 << BITS))


def sobol_engine(d: int, rng: np.random.Generator) -> ScrambledSobol | qmc.Sobol:
    """An engine with ``random(n)`` giving ``scipy.stats.qmc.Sobol(d, scramble=True, seed=rng)``'s points."""
    numbers = _direction_numbers() if d <= KEPT_DIMENSIONS else _direction_numbers(d)
    if numbers is None or d > numbers[0].shape[0]:
        from scipy.stats import qmc

        return qmc.Sobol(d=d, scramble=True, seed=rng)
    return ScrambledSobol(d, rng, numbers)
