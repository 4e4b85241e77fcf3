"""Pairwise (and 1-wise) covering arrays at community scale: one product at a time, the
uncovered pairs as a bit matrix.

Why a bit matrix: a community-size model has millions of pairs (automotive01's 2,234 free
features have 9,977,044), too many to list one tuple each and far too many to visit one
by one in Python. Here literal ``i`` is the ``i``-th free feature and ``m + i`` its
negation, and the pairs still to cover are a matrix of bits, a row per literal packed in
64-bit words (bit ``b`` of row ``a``: the pair ``a, b`` is neither covered nor known
invalid), 2.5 MB for automotive01. A literal's need is a popcount of its row, what a
decision adds to every literal's score is the sum of a few unpacked rows, and covering a
product is one AND of its literals' rows with the complement of the product. numpy (a
dependency for the samplers alone) does these in C: the greedy below rescores all 4,468
literals of automotive01 after every decision, about two thousand decisions per
product, which as interpreted loops would cost seconds per product instead of
milliseconds (a boolean matrix of 20 MB, summed and assigned by numpy, still took 81 s
for automotive01, the packed rows 30 s).

The construction is the greedy one of IncLing (Al-Hajjaji, Krieter, Thüm, Lochau, Saake:
"IncLing: Efficient Product-Line Testing using Incremental Pairwise Sampling", GPCE
2016) and of ICPL's Chvátal heuristic: products are built one at a time, each to cover
as many still uncovered pairs as it can, with the SAT solver deciding validity (as YASA
does: Krieter, Thüm, Schulze, Leich, Saake, "YASA: Yet Another Sampling Algorithm",
VaMoS 2020):

1. Pairs unit propagation refutes (``a`` propagates ``not b``, or ``b`` ``not a``) are
   invalid at the start, without a solver call: one propagation per literal, computed
   once, whose result (the literals each literal implies) is kept.
2. A product starts from a *seed*, an uncovered pair: the literal in the most uncovered
   pairs and, of its partners, the one in the most. When the solver refutes the seed, it
   is invalid, counted, and another seed is chosen.
3. Then, while some open literal still has uncovered pairs, the literal covering the most
   uncovered pairs with the product's literals so far is decided (ties: the literal in
   more uncovered pairs, then the first). The solver is asked only when that literal is
   not in the last model found (a product with everything decided so far) and what it
   implies does not already contradict the product; a refuted literal's negation is
   decided instead (every product with the decided literals has it).
4. The product is the last model, and all of its pairs are covered at once.

Every product covers its seed, so the loop ends, and a pair leaves the matrix only when a
product contains it or the solver (or propagation) refutes it: covered plus invalid is
the number of pairs. Each step depends only on the model (numpy's argmax takes the first
maximum), so the same model gives the same sample, byte for byte.
"""

from __future__ import annotations

import math

import numpy as np
from pysat.solvers import Solver


class GreedyCover:
    """The products built over ``features`` (free variables, in model order) for t."""

    def __init__(self, solver: Solver, features: list[int], t: int) -> None:
        self.solver = solver
        self.t = t
        m = self.m = len(features)
        size = 2 * m
        self.literal = [*features, *(-v for v in features)]
        self.negation = np.concatenate([np.arange(m, size), np.arange(m)])
        self.model_index = np.array(features, dtype=np.int64) - 1
        position = {lit: i for i, lit in enumerate(self.literal)}
        self.implied = [self._implied(lit, position) for lit in self.literal]
        self.models: list[np.ndarray] = []
        self.solver_calls = 0
        self.total = math.comb(m, t) * 2**t
        self.words = (size + 63) // 64  # a row of bits, one per literal, in 64-bit words
        self.uncovered = self._start()
        self.invalid = self.total - self._open()

    # --- what t decides (spl.resolver.analysis.triple_cover overrides these for t = 3) ------
    def _start(self) -> np.ndarray:
        """The combinations to cover: for t = 1 a vector of booleans, for t = 2 the pair
        matrix, a row of bits per literal."""
        if self.t == 1:
            return np.ones(2 * self.m, dtype=bool)
        return self._pack(self._valid_pairs())

    def _pack(self, bits: np.ndarray) -> np.ndarray:
        """Rows of booleans as rows of 64-bit words (bit ``c`` in word ``c // 64``)."""
        packed = np.packbits(bits, axis=-1, bitorder="little")
        padded = np.zeros((*packed.shape[:-1], self.words * 8), dtype=np.uint8)
        padded[..., : packed.shape[-1]] = packed
        return padded.view(np.uint64)

    def _unpack(self, words: np.ndarray) -> np.ndarray:
        return np.unpackbits(words.view(np.uint8), axis=-1, count=2 * self.m, bitorder="little")

    def _implied(self, lit: int, position: dict[int, int]) -> np.ndarray:
        ok, lits = self.solver.propagate(assumptions=[lit])
        assert ok, "free literals propagate without conflict"
        return np.array(sorted({position[x] for x in lits if x in position}), dtype=np.int64)

    def _valid_pairs(self) -> np.ndarray:
        """Every pair of literals of two features that propagation does not refute."""
        size = 2 * self.m
        pairs = np.ones((size, size), dtype=bool)
        for a, implied in enumerate(self.implied):
            pairs[a, self.negation[implied]] = False
        pairs &= pairs.T
        every = np.arange(size)
        pairs[every, every] = False
        pairs[every, self.negation] = False
        return pairs

    def _open(self) -> int:
        """How many combinations are still uncovered (and not known invalid)."""
        if self.t == 1:
            return int(np.count_nonzero(self.uncovered))
        return int(np.bitwise_count(self.uncovered).sum()) // 2

    def _solve(self, assumptions: list[int]) -> np.ndarray | None:
        """The free literals of a product with ``assumptions``, or None if there is none."""
        self.solver_calls += 1
        if not self.solver.solve(assumptions=assumptions):
            return None
        selected = np.array(self.solver.get_model(), dtype=np.int64)[self.model_index] > 0
        return np.concatenate([selected, ~selected])

    # --- the algorithm -------------------------------------------------------------
    def build(self) -> None:
        need = self._need()
        while True:
            seed = self._seed(need)
            if seed is None:
                return
            model = self._solve([self.literal[b] for b in seed])
            if model is None:
                self._refute(seed, need)
                self.invalid += 1
                continue
            model = self._complete(seed, model, need.copy())
            self.models.append(model)
            self._cover(np.flatnonzero(model))
            need = self._need()

    def _clear(self, row: int, bit: int) -> None:
        self.uncovered[row, bit >> 6] &= ~np.uint64(1 << (bit & 63))

    def _refute(self, seed: tuple[int, ...], need: np.ndarray) -> None:
        """Drop a combination the solver refuted (only pairs can be: every free literal
        is in some product), from the bits and from ``need``."""
        a, b = seed
        self._clear(a, b)
        self._clear(b, a)
        need[[a, b]] -= 1

    def _cover(self, chosen: np.ndarray) -> None:
        """Mark every combination of the literals ``chosen`` covered."""
        if self.t == 1:
            self.uncovered[chosen] = False
            return
        inside = np.zeros(2 * self.m, dtype=bool)
        inside[chosen] = True
        self.uncovered[chosen] &= ~self._pack(inside)

    def _need(self) -> np.ndarray:
        """Per literal, how many uncovered combinations it is in (or a multiple)."""
        if self.t == 1:
            return self.uncovered.astype(np.int64)
        return np.bitwise_count(self.uncovered).sum(axis=1, dtype=np.int64)

    def _gains(self, new: np.ndarray, before: np.ndarray) -> np.ndarray | None:
        """Per literal, the uncovered combinations it would now complete that literals
        ``new`` make possible, ``before`` being the product's literals until then."""
        if self.t == 1 or not new.size:
            return None
        return self._unpack(self.uncovered[new]).sum(axis=0, dtype=np.int64)

    def _seed(self, need: np.ndarray) -> tuple[int, ...] | None:
        """The uncovered combination to start a product from, or None when all are
        covered: the literal in the most uncovered pairs, with its partner in the most
        (starting from the first uncovered pair instead gives 713 products for
        automotive01, not 672)."""
        if self.t == 1:
            rest = np.flatnonzero(self.uncovered)
            return (int(rest[0]),) if rest.size else None
        a = int(np.argmax(need))
        if need[a] == 0:
            return None
        partners = self._unpack(self.uncovered[a]).astype(bool)
        return a, int(np.argmax(np.where(partners, need, -1)))

    def _complete(self, seed: tuple[int, ...], model: np.ndarray, score: np.ndarray) -> np.ndarray:
        """Decide the product that starts from ``seed``; its free literals. ``score``
        starts as each literal's need and is the greedy's working array."""
        size = 2 * self.m
        weight = int(score.max()) + 1  # a covered combination outweighs any tie-break
        closed = -(2**62)  # below anything the additions can bring back over 0
        in_product = np.zeros(size, dtype=bool)
        decided: list[int] = []

        def take(b: int) -> None:
            decided.append(self.literal[b])
            implied = self.implied[b]
            new = implied[~in_product[implied]]
            gains = self._gains(new, np.flatnonzero(in_product))
            in_product[new] = True
            if gains is not None:
                score[:] += weight * gains
            score[new] = closed
            score[self.negation[new]] = closed

        for b in seed:
            take(b)
        while True:
            b = int(np.argmax(score))
            if score[b] <= 0:
                return model
            if model[b]:
                take(b)
            elif in_product[self.negation[self.implied[b]]].any():
                take(int(self.negation[b]))
            else:
                found = self._solve([*decided, self.literal[b]])
                if found is None:
                    take(int(self.negation[b]))
                else:
                    model = found
                    take(b)

    def selected(self, model: np.ndarray) -> list[int]:
        """The positions (in ``features``) of the free features a model selects."""
        return [int(i) for i in np.flatnonzero(model[: self.m])]
