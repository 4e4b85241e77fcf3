"""Covering arrays of the community's real models, checked by an oracle that shares
nothing with the sampler but the CNF: a fresh MiniSat (the sampler runs Glucose on the
formula with its backbone fixed) decides that every product satisfies the formula and
which randomly drawn combinations are valid, and each valid one must be in some
product. Every product is also checked against the feature tree and constraints
directly (fm_semantics.is_product, no CNF). automotive01 (2,513 features, about a minute)
is checked the same way by bench/sampling.py, not here.
"""

from __future__ import annotations

import random

from pysat.solvers import Solver

from spl.dsl.interop.formats import load_feature_model
from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.analysis.sampling import covering_array

from support.fm_semantics import is_product
from support.real_models import REAL_MODELS

BUSYBOX = REAL_MODELS / "busybox_2010-05-02_14-17-07.uvl"
Combination = tuple[tuple[str, bool], ...]


def draw(names: list[str], t: int, count: int, seed: int) -> list[Combination]:
    """``count`` combinations of t literals of distinct features, drawn with a seeded RNG."""
    rng = random.Random(seed)
    return [
        tuple((name, rng.random() < 0.5) for name in rng.sample(names, t)) for _ in range(count)
    ]


def split_by_oracle(
    formula: FeatureModelFormula, products: tuple[frozenset[str], ...], drawn: list[Combination]
) -> tuple[list[Combination], int]:
    """Check every product with a fresh solver; return the valid drawn combinations and
    how many were invalid."""
    cnf = formula.cnf
    valid = []
    with Solver(name="minisat22", bootstrap_with=list(cnf.clauses)) as oracle:
        for product in products:
            assignment = [
                cnf.var[name] if name in product else -cnf.var[name] for name in cnf.names
            ]
            assert oracle.solve(assumptions=assignment), sorted(product)
        for combination in drawn:
            literals = [cnf.var[name] if value else -cnf.var[name] for name, value in combination]
            if oracle.solve(assumptions=literals):
                valid.append(combination)
    return valid, len(drawn) - len(valid)


def uncovered(products: tuple[frozenset[str], ...], combinations: list[Combination]) -> list:
    return [
        combination
        for combination in combinations
        if not any(
            all((name in product) == value for name, value in combination) for product in products
        )
    ]


def test_busybox_pairwise_sample_is_valid_and_covers_random_valid_pairs() -> None:
    model = load_feature_model(BUSYBOX)
    formula = FeatureModelFormula(model)
    sample = covering_array(formula, 2)
    assert all(is_product(model, product) for product in sample.products)
    valid, invalid = split_by_oracle(formula, sample.products, draw(formula.cnf.names, 2, 4000, 7))
    assert len(valid) >= 3000 and invalid > 0  # the draw meets both kinds
    assert not uncovered(sample.products, valid)
    # not vacuous: half of the sample misses some of the drawn valid pairs
    assert uncovered(sample.products[: len(sample.products) // 2], valid)
    assert sample.covered + sample.invalid == 622 * 621 // 2 * 4
    # no larger than the 35 products of the sampler this one replaced
    assert len(sample.products) <= 35


def test_pairwise_sample_is_deterministic_on_busybox() -> None:
    first = covering_array(FeatureModelFormula(load_feature_model(BUSYBOX)), 2).products
    again = covering_array(FeatureModelFormula(load_feature_model(BUSYBOX)), 2).products
    assert again == first


def test_three_wise_sample_of_axtls_covers_random_valid_triples() -> None:
    model = load_feature_model(REAL_MODELS / "axTLS.uvl")
    formula = FeatureModelFormula(model)
    sample = covering_array(formula, 3)
    assert all(is_product(model, product) for product in sample.products)
    valid, invalid = split_by_oracle(formula, sample.products, draw(formula.cnf.names, 3, 3000, 11))
    assert len(valid) >= 1500 and invalid > 0
    assert not uncovered(sample.products, valid)
    assert uncovered(sample.products[: len(sample.products) // 2], valid)
