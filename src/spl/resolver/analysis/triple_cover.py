"""3-wise covering arrays: the greedy of :mod:`spl.resolver.analysis.covering` over a bit cube.

Why a cube, and how large: for t = 3 a product's worth is the number of uncovered
triples it completes, so the uncovered triples are kept as one row of bits per pair of
literals (row ``a, b`` has bit ``c`` when the triple ``a, b, c`` is uncovered), packed
64 to a word: one bit per (pair, literal), 124 MB for BusyBox's 622 free features
(319,309,920 triples, which as tuples would take tens of gigabytes). A product's new
literal ``y`` then adds to every open literal's score the bits of the rows ``y, z`` for
the product's literals ``z``; covering a product clears its literals' bits in the rows
of all of its pairs at once. Beyond :data:`MAX_CUBE_BYTES` (automotive01 would need
5.2 GiB) the sample is refused with the figure.

Validity: every triple of a pair that is not valid is invalid, so the cube starts from
the exact valid pairs, those a pairwise sample covers (every valid pair is in one of its
products). A triple all of whose pairs are valid can still be invalid; the solver
refutes it when it comes up as a seed.
"""

from __future__ import annotations

import numpy as np
from pysat.solvers import Solver

from spl.resolver.analysis.covering import GreedyCover

MAX_CUBE_BYTES = 1 << 30  # 1 GiB of uncovered-triple bits


class CubeTooLarge(ValueError):
    """More uncovered-triple bits than :data:`MAX_CUBE_BYTES`."""


def refuse_large_cube(features: int) -> None:
    """Raise :class:`CubeTooLarge` when ``features`` free features need too large a cube
    (checked before any product is built)."""
    size = 2 * features
    cube = (size * (size - 1) // 2 + 1) * ((size + 63) // 64) * 8
    if cube > MAX_CUBE_BYTES:
        raise CubeTooLarge(
            f"3-wise sampling of {features} free features keeps {cube / 2**30:.1f} GiB of "
            f"triple bits, more than the {MAX_CUBE_BYTES // 2**30} GiB spl allows; use t = 2"
        )


class TripleCover(GreedyCover):
    """The 3-wise products over ``features``, given the exact valid pairs."""

    def __init__(self, solver: Solver, features: list[int], valid_pairs: np.ndarray) -> None:
        refuse_large_cube(len(features))
        self.valid_pairs = valid_pairs
        super().__init__(solver, features, 3)

    def _start(self) -> np.ndarray:
        size = 2 * self.m
        first, second = np.triu_indices(size, k=1)
        self.first, self.second = first, second
        dummy = first.size  # an all-zero row for the pair of a literal with itself
        self.row = np.full((size, size), dummy, dtype=np.int64)
        self.row[first, second] = self.row[second, first] = np.arange(first.size)
        cube = np.zeros((first.size + 1, self.words), dtype=np.uint64)
        valid = self.valid_pairs
        for start in range(0, first.size, 8192):
            a, b = first[start : start + 8192], second[start : start + 8192]
            bits = valid[a] & valid[b] & valid[a, b][:, None]
            cube[start : start + a.size] = self._pack(bits)
        return cube

    def _open(self) -> int:
        return int(np.bitwise_count(self.uncovered).sum()) // 3

    def _need(self) -> np.ndarray:
        per_row = np.bitwise_count(self.uncovered[:-1]).sum(axis=1, dtype=np.int64)
        size = 2 * self.m
        need = np.bincount(self.first, per_row, size) + np.bincount(self.second, per_row, size)
        return need.astype(np.int64)

    def _seed(self, need: np.ndarray) -> tuple[int, ...] | None:
        a = int(np.argmax(need))
        if need[a] == 0:
            return None
        rows = self.row[a]
        b = int(np.argmax(np.bitwise_count(self.uncovered[rows]).sum(axis=1)))
        bits = self._unpack(self.uncovered[self.row[a, b]]).astype(bool)
        return a, b, int(np.argmax(np.where(bits, need, -1)))

    def _refute(self, seed: tuple[int, ...], need: np.ndarray) -> None:
        a, b, c = seed
        for x, y, other in ((a, b, c), (a, c, b), (b, c, a)):
            self._clear(int(self.row[x, y]), other)
        need[[a, b, c]] -= 2  # each literal of a triple is in two of its three rows

    def _cover(self, chosen: np.ndarray) -> None:
        inside = np.zeros(2 * self.m, dtype=bool)
        inside[chosen] = True
        mask = self._pack(inside)
        upper = np.triu_indices(chosen.size, k=1)
        rows = self.row[chosen[upper[0]], chosen[upper[1]]]
        self.uncovered[rows] &= ~mask

    def _gains(self, new: np.ndarray, before: np.ndarray) -> np.ndarray | None:
        upper = np.triu_indices(new.size, k=1)
        rows = np.concatenate(
            [self.row[np.ix_(new, before)].ravel(), self.row[new[upper[0]], new[upper[1]]]]
        )
        if not rows.size:
            return None
        return self._unpack(self.uncovered[rows]).sum(axis=0, dtype=np.int64)


def valid_pairs(pairwise: GreedyCover) -> np.ndarray:
    """The pairs of literals some product of a complete pairwise sample has: exactly the
    valid pairs."""
    size = 2 * pairwise.m
    found = np.zeros((size, size), dtype=bool)
    for model in pairwise.models:
        chosen = np.flatnonzero(model)
        found[np.ix_(chosen, chosen)] = True
    found[np.arange(size), np.arange(size)] = False
    return found
