"""t-wise covering arrays, random and complete enumeration, checked independently.

Small models: every product is enumerated by brute force (tests/fm_semantics.py walks
the tree), so the valid t-combinations are known exactly and the sample must contain
each of them. Real models (BerkeleyDB, axTLS): every sampled product is checked against
the tree and constraints, and every pair the sample misses must be refuted by a
separate SAT solver (MiniSat, not the Glucose instance the sampler uses).
"""

from __future__ import annotations

from itertools import combinations
from pathlib import Path

import pytest
from pysat.solvers import Solver

from spl.dsl.fm.language import parse_file
from spl.dsl.interop.formats import load_feature_model
from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.analysis.sampling import covering_array, product_key, random_products

from support.fm_semantics import is_product, products as brute_force_products
from support.real_models import REAL_MODELS
from support.sample_checks import interactions

ROOT = Path(__file__).resolve().parents[2]
MODELS = Path(__file__).parents[1] / "models"
SMALL = [
    ROOT / "product_lines/mapping3d/mapping.fm",
    ROOT / "product_lines/data_acquisition/data.fm",
    MODELS / "fm/all_constructs.fm",
    MODELS / "fm/spec_example.fm",
    MODELS / "analysis/mapping.fm",
    MODELS / "validate/conflicting/conflicting.fm",
    MODELS / "validate/sampling/search.fm",
]


@pytest.fixture(scope="module")
def brute_force():
    """path -> (model, every product, feature names), each enumerated once."""
    found = {}
    for path in SMALL:
        model = parse_file(path)
        formula = FeatureModelFormula(model)
        found[path] = (model, brute_force_products(model), list(formula.cnf.names))
    return found


@pytest.mark.parametrize("t", [1, 2])
@pytest.mark.parametrize("path", SMALL, ids=lambda p: p.stem)
def test_sample_covers_every_valid_combination(brute_force, path: Path, t: int) -> None:
    model, products, names = brute_force[path]
    sample = covering_array(FeatureModelFormula(model), t)
    assert sample.products, "every model here has products"
    assert all(product in products for product in sample.products)
    assert len(set(sample.products)) == len(sample.products)
    missing = interactions(products, names, t) - interactions(sample.products, names, t)
    assert not missing
    assert len(sample.products) <= len(products)


@pytest.mark.parametrize("path", [p for p in SMALL if "search" not in p.name], ids=lambda p: p.stem)
def test_three_wise_sample(brute_force, path: Path) -> None:
    model, products, names = brute_force[path]
    sample = covering_array(FeatureModelFormula(model), 3)
    assert all(product in products for product in sample.products)
    assert not interactions(products, names, 3) - interactions(sample.products, names, 3)


def test_invalid_pairs_found_by_search_are_excluded_and_counted(brute_force) -> None:
    path = MODELS / "validate/sampling/search.fm"
    model, products, names = brute_force[path]
    core = set.intersection(*map(set, products))
    dead = set(names) - set.union(*map(set, products))
    free = [name for name in names if name not in core | dead]
    valid = interactions(products, free, 2)
    sample = covering_array(FeatureModelFormula(model), 2)
    assert sample.covered == len(valid)
    assert sample.invalid == 4 * len(free) * (len(free) - 1) // 2 - len(valid)
    # P and Q never meet: no unit propagation of either one refutes the other
    assert (("P", True), ("Q", True)) not in valid
    assert not any({"P", "Q"} <= product for product in sample.products)
    assert "Ghost" in dead


def test_sample_is_deterministic() -> None:
    model = parse_file(MODELS / "fm/all_constructs.fm")
    first = covering_array(FeatureModelFormula(model), 2).products
    assert covering_array(FeatureModelFormula(model), 2).products == first


def test_void_model_has_an_empty_sample() -> None:
    sample = covering_array(FeatureModelFormula(parse_file(MODELS / "analysis/void.fm")), 2)
    assert sample.products == () and sample.covered == 0


def test_t_out_of_range_is_refused() -> None:
    formula = FeatureModelFormula(parse_file(MODELS / "fm/spec_example.fm"))
    with pytest.raises(ValueError, match=r"t = 1\.\.3"):
        covering_array(formula, 4)


@pytest.mark.parametrize("name", ["berkeleydb.uvl", "axTLS.uvl"])
def test_pairwise_sample_of_real_models(name: str) -> None:
    model = load_feature_model(REAL_MODELS / name)
    formula = FeatureModelFormula(model)
    sample = covering_array(formula, 2)
    assert all(is_product(model, product) for product in sample.products)
    cnf = formula.cnf
    covered = interactions(sample.products, cnf.names, 2)
    with Solver(name="minisat22", bootstrap_with=list(cnf.clauses)) as solver:
        for a, b in combinations(cnf.names, 2):
            for va in (True, False):
                for vb in (True, False):
                    if ((a, va), (b, vb)) in covered:
                        continue
                    assumptions = [
                        cnf.var[a] if va else -cnf.var[a],
                        cnf.var[b] if vb else -cnf.var[b],
                    ]
                    assert not solver.solve(assumptions=assumptions), (a, va, b, vb)


def test_random_products_are_distinct_valid_and_reproducible(brute_force) -> None:
    path = MODELS / "fm/all_constructs.fm"
    model, products, _ = brute_force[path]
    drawn = list(random_products(FeatureModelFormula(model), 20, seed=7))
    assert len(drawn) == 20 and len(set(drawn)) == 20
    assert all(product in products for product in drawn)
    assert list(random_products(FeatureModelFormula(model), 20, seed=7)) == drawn
    assert list(random_products(FeatureModelFormula(model), 20, seed=8)) != drawn
    # asking for more than exist gives each product once
    everything = list(random_products(FeatureModelFormula(model), 500, seed=1))
    assert set(everything) == products and len(everything) == len(products)


def test_enumeration_is_lazy_and_complete(brute_force) -> None:
    model, products, _ = brute_force[MODELS / "fm/all_constructs.fm"]
    formula = FeatureModelFormula(model)
    stream = formula.products()
    first = next(stream)  # found before the rest are enumerated
    assert first in products
    assert {first, *stream} == products


def test_product_key_determines_the_product(brute_force) -> None:
    model, products, _ = brute_force[ROOT / "product_lines/mapping3d/mapping.fm"]
    formula = FeatureModelFormula(model)
    keys = {tuple(product_key(formula, product)) for product in products}
    assert len(keys) == len(products)
    assert ("YouBot", "Stereo", "AdditionalPC", "Room") in keys
