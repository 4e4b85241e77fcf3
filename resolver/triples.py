"""3-wise covering arrays of small and medium models, by listing the combinations.

Why a second algorithm: the bit matrix of :mod:`spl.resolver.covering` has a row per
literal and a column per partner; for t = 3 its analogue would have a row per *pair*,
which the greedy there would have to sum over for every decision. Triples are therefore
built the way every t was before: incremental greedy construction in the manner of
IncLing (Al-Hajjaji, Krieter, Thüm, Lochau, Saake: "IncLing: Efficient Product-Line
Testing using Incremental Pairwise Sampling", GPCE 2016), with the SAT solver deciding
every candidate (as in YASA, Krieter et al., VaMoS 2020):

1. The free literals' t-combinations are listed; those unit propagation refutes (``A``
   propagates ``not B``) are invalid without a SAT call.
2. A new product starts empty. The uncovered combinations are visited in one fixed
   pseudo-random order (seeded, so the sample is deterministic; consecutive
   combinations then rarely share a literal, which keeps a product from being decided
   by the partners of a single literal). A combination is added to the product when it
   does not contradict the literals decided or propagated so far and the solver finds a
   product with all of them (the last model found is tried first, without a call).
   While the product is still empty, a combination the solver refutes is invalid.
3. When the pass ends the solver completes the product; every combination it contains
   is covered. Repeat until nothing is uncovered.

Every product holds at least the first combination of its pass, so the loop ends; and
every valid combination is covered because it stays listed until a product contains it.
The listing is bounded by :data:`MAX_COMBINATIONS` (a tuple each in memory).
"""

from __future__ import annotations

import math
import random
from itertools import combinations

from pysat.solvers import Solver

# The combinations are listed in memory (a tuple each): beyond this many, refuse with
# the number rather than exhaust memory (t = 3 over BusyBox's 622 free features would be
# 320 million).
MAX_COMBINATIONS = 5_000_000

ORDER_SEED = 20160809  # fixed: the same model always gives the same sample


class SampleTooLarge(ValueError):
    """More t-combinations than :data:`MAX_COMBINATIONS`."""


def listed_cover(
    solver: Solver, free: list[int], n: int, t: int
) -> tuple[list[list[int]], int, int]:
    """The products (models over the first ``n`` variables) covering every valid
    t-combination of the literals of ``free``, with the covered and invalid counts."""
    literals = [lit for v in free for lit in (v, -v)]
    total = math.comb(len(free), t) * 2**t
    if total > MAX_COMBINATIONS:
        raise SampleTooLarge(
            f"{t}-wise sampling of {len(free)} free features means {total:,} combinations, "
            f"more than the {MAX_COMBINATIONS:,} spl lists for t = {t}; use a smaller t"
        )
    implied = {}
    for lit in literals:
        ok, lits = solver.propagate(assumptions=[lit])
        implied[lit] = set(lits) if ok else {lit, -lit}
    pending: list[tuple[int, ...]] = []
    invalid = 0
    for combination in combinations(literals, t):
        if len({abs(lit) for lit in combination}) < t:
            continue
        if any(-other in implied[lit] for lit in combination for other in combination):
            invalid += 1
        else:
            pending.append(combination)
    random.Random(ORDER_SEED).shuffle(pending)
    covered = 0
    products: list[list[int]] = []
    while pending:
        model, refuted = _next_product(solver, pending, n)
        invalid += len(refuted)
        chosen = set(model)
        remaining = []
        for combination in pending:
            if combination in refuted:
                continue
            if all(lit in chosen for lit in combination):
                covered += 1
            else:
                remaining.append(combination)
        pending = remaining
        if model:
            products.append(model)
    return products, covered, invalid


def _next_product(
    solver: Solver, pending: list[tuple[int, ...]], n: int
) -> tuple[list[int], set[tuple[int, ...]]]:
    """One greedy pass: the product's feature literals and the combinations found invalid
    while it was still empty (an empty model when every pending one was invalid)."""
    decided: list[int] = []
    members: set[int] = set()  # decided and propagated feature literals
    model: list[int] | None = None  # a product with every decided literal
    in_model: set[int] = set()
    refuted: set[tuple[int, ...]] = set()
    for combination in pending:
        new = []
        for lit in combination:
            if -lit in members:
                break
            if lit not in members:
                new.append(lit)
        else:
            if not new:
                continue
            if not all(lit in in_model for lit in new):
                assumptions = decided + new
                ok, _ = solver.propagate(assumptions=assumptions)
                if not ok or not solver.solve(assumptions=assumptions):
                    if not decided:
                        refuted.add(combination)
                    continue
                model = solver.get_model()[:n]
                in_model = set(model)
            decided.extend(new)
            ok, lits = solver.propagate(assumptions=decided)
            members.update(lit for lit in lits if abs(lit) <= n)
    if model is None:
        return [], refuted
    solver.solve(assumptions=decided)
    return solver.get_model()[:n], refuted
