"""Which products to test: all of them, a t-wise covering array, or a random few.

A product line with a dozen optional features already has thousands of products; CI
cannot derive them all, but most faults are triggered by the interaction of one or two
features. A *t-wise covering array* is a set of valid products in which every valid
combination of ``t`` feature literals (``f``, ``not f``; for t = 2 the four
combinations of each pair) appears at least once. Combinations no product contains
(e.g. ``Roomba and AdditionalPC`` when one excludes the other) are *invalid* and
excluded; they are found with the SAT solver (or unit propagation), never assumed.

Core and dead features (the backbone) are left out first: their literals are in every /
no product, so combinations with them are covered by the others or invalid. The rest is
built by :mod:`spl.resolver.analysis.covering` for t = 1 and 2 (one product at a time, the
uncovered pairs as a bit matrix, so that community-size models such as automotive01
sample in seconds) and by :mod:`spl.resolver.analysis.triple_cover` for t = 3. How, and how large
the
samples are: docs/analysis.md (Sampling) and docs/performance.md (Pairwise sampling).
"""

from __future__ import annotations

import random
import time
from collections.abc import Iterator
from dataclasses import dataclass

from pysat.solvers import Solver

from spl.resolver.analysis.covering import GreedyCover
from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.analysis.triple_cover import TripleCover, refuse_large_cube, valid_pairs

MAX_T = 3


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
    if t == 3:
        refuse_large_cube(len(free))
    with Solver(name=formula.solver_name, bootstrap_with=list(cnf.clauses) + fixed) as solver:
        if t <= 2:
            cover = GreedyCover(solver, free, t)
            cover.build()
        else:
            pairwise = GreedyCover(solver, free, 2)
            pairwise.build()
            cover = TripleCover(solver, free, valid_pairs(pairwise))
            cover.build()
        chosen = [[free[i] for i in cover.selected(model)] for model in cover.models]
        covered, invalid = cover.total - cover.invalid, cover.invalid
    products = tuple(frozenset(core | {cnf.names[v - 1] for v in vs}) for vs in chosen)
    return Sample(t, products, covered, invalid, time.perf_counter() - start)


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
