"""Which products to test: all of them, a t-wise covering array, or a random few.

A product line with a dozen optional features already has thousands of products; CI
cannot derive them all, but most faults are triggered by the interaction of one or two
features. A *t-wise covering array* is a set of valid products in which every valid
combination of ``t`` feature literals (``f``, ``not f``; for t = 2 the four
combinations of each pair) appears at least once. Combinations no product contains
(e.g. ``Roomba and AdditionalPC`` when one excludes the other) are *invalid* and
excluded; they are found with the SAT solver, never assumed.

Algorithm: incremental greedy construction in the manner of IncLing (Al-Hajjaji,
Krieter, Thüm, Lochau, Saake: "IncLing: Efficient Product-Line Testing using Incremental
Pairwise Sampling", GPCE 2016, doi:10.1145/2993236.2993253) — products are built one
at a time, each from the combinations no earlier product covers — with the SAT solver
deciding every candidate (as in YASA, Krieter et al., VaMoS 2020):

1. Core and dead features (the backbone) are left out: their literals are in every /
   no product, so combinations with them are covered by the others or invalid. The
   remaining literals' t-combinations are listed; those unit propagation refutes
   (``A`` propagates ``not B``) are invalid without a SAT call.
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
"""

from __future__ import annotations

import math
import random
import time
from collections.abc import Iterator
from dataclasses import dataclass
from itertools import combinations

from pysat.solvers import Solver

from spl.resolver.analysis import FeatureModelFormula

MAX_T = 3
# The combinations are listed in memory (a tuple each): beyond this many, refuse with
# the number rather than exhaust memory (t = 3 over BusyBox's 622 free features would be
# 320 million).
MAX_COMBINATIONS = 5_000_000


ORDER_SEED = 20160809  # fixed: the same model always gives the same sample


class SampleTooLarge(ValueError):
    """More t-combinations than :data:`MAX_COMBINATIONS`."""


@dataclass(frozen=True)
class Sample:
    """A t-wise covering array and what it covers."""

    t: int
    products: tuple[frozenset[str], ...]
    covered: int  # valid t-combinations of literals of non-core, non-dead features
    invalid: int  # t-combinations no product contains (excluded)
    seconds: float


def covering_array(formula: FeatureModelFormula, t: int = 2) -> Sample:
    """A set of products covering every valid t-wise combination of feature literals."""
    if not 1 <= t <= MAX_T:
        raise ValueError(f"t-wise sampling supports t = 1..{MAX_T}, not {t}")
    start = time.perf_counter()
    if not formula.satisfiable():
        return Sample(t, (), 0, 0, time.perf_counter() - start)
    cnf = formula.cnf
    n = cnf.num_features
    core, dead = formula.backbone()
    fixed = [(cnf.var[name],) for name in core] + [(-cnf.var[name],) for name in dead]
    free = [v for v in range(1, n + 1) if cnf.names[v - 1] not in core | dead]
    literals = [lit for v in free for lit in (v, -v)]
    total = math.comb(len(free), t) * 2**t
    if total > MAX_COMBINATIONS:
        raise SampleTooLarge(
            f"{t}-wise sampling of {len(free)} free features means {total:,} combinations, "
            f"more than the {MAX_COMBINATIONS:,} spl samples; use a smaller t"
        )
    with Solver(name=formula.solver_name, bootstrap_with=list(cnf.clauses) + fixed) as solver:
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
        products: list[frozenset[str]] = []
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
                products.append(frozenset(cnf.names[lit - 1] for lit in model if lit > 0))
    return Sample(t, tuple(products), covered, invalid, time.perf_counter() - start)


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


def random_products(
    formula: FeatureModelFormula, count: int, seed: int
) -> Iterator[frozenset[str]]:
    """Up to ``count`` distinct products, reproducible from ``seed``.

    Distribution (not uniform): for each product every feature gets a preferred
    polarity by a fair coin (``random.Random(seed)``), the SAT solver finds a product
    following those preferences as far as the constraints allow, and the product is
    blocked so it is not drawn again. Products that many polarity vectors lead to
    (e.g. those of a feature forced by many others) are more likely than under uniform
    sampling. Fewer than ``count`` products are returned only when the model has fewer.
    """
    rng = random.Random(seed)
    cnf = formula.cnf
    n = cnf.num_features
    with Solver(name=formula.solver_name, bootstrap_with=list(cnf.clauses)) as solver:
        for _ in range(count):
            solver.set_phases([v if rng.random() < 0.5 else -v for v in range(1, n + 1)])
            if not solver.solve():
                return
            model = solver.get_model()[:n]
            yield frozenset(cnf.names[lit - 1] for lit in model if lit > 0)
            solver.add_clause([-lit for lit in model])


def product_key(formula: FeatureModelFormula, product: frozenset[str]) -> list[str]:
    """The features of ``product`` that are not core, in feature-model order.

    Given as a selection they determine the product (the completion adds the core and
    leaves every other feature out), and they are short enough to name it.
    """
    core = formula.backbone()[0]
    return [name for name in formula.cnf.names if name in product and name not in core]
