"""Differential test: random small feature models, every operation against brute force.

The models are drawn with a fixed seed (deterministic), with every group kind, cardinality
bounds, and cross-tree constraints of every operator; the expected answers come from the
brute-force evaluator of tests/analysis_models.py, which knows nothing of CNF or SAT.
"""

from __future__ import annotations

import random

import pytest

from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.resolution.selection import check_selection

from support.analysis_models import (
    all_features,
    binary,
    brute_force_products,
    constraint,
    feature,
    group,
    model,
    negate,
    ref,
)

OPERATORS = ["and", "or", "implies", "iff", "requires", "excludes"]


def random_model(rng: random.Random):
    count = [0]

    def new_feature(depth: int):
        count[0] += 1
        name = f"F{count[0]}"
        groups = []
        if depth < 3 and count[0] < 8:
            for _ in range(rng.randint(1 if depth == 0 else 0, 2)):
                kind = rng.choice(["mandatory", "optional", "alternative", "or", "cardinality"])
                size = min(rng.randint(1, 3), 9 - count[0])
                if size < 1:
                    break
                members = [new_feature(depth + 1) for _ in range(size)]
                lower, upper = 0, -1
                if kind == "cardinality":
                    lower = rng.randint(0, len(members))
                    upper = rng.choice([-1, rng.randint(lower, len(members) + 1)])
                groups.append(group(kind, *members, lower=lower, upper=upper))
        return feature(name, *groups)

    m = model(new_feature(0))
    for line in range(rng.randint(0, 3)):
        formula = random_formula(rng, all_features(m), 2, leaf=0.4, negated_leaf=0.2)
        m.constraints.append(constraint(formula, 20 + line))
    return m


def random_formula(
    rng: random.Random,
    fs: dict,
    depth: int,
    leaf: float,
    negated_leaf: float,
    iff: float = 0.0,
    negated: float = 0.0,
):
    """A random constraint over the features ``fs``, at most ``depth`` operators deep:
    a leaf with probability ``leaf`` (negated with ``negated_leaf``), else an operator, an
    iff with probability ``iff`` (any operator otherwise), negated with ``negated``."""
    if depth == 0 or rng.random() < leaf:
        node = ref(rng.choice(sorted(fs)), fs)
        return negate(node) if rng.random() < negated_leaf else node
    operator = "iff" if iff and rng.random() < iff else rng.choice(OPERATORS)
    node = binary(
        operator,
        *(random_formula(rng, fs, depth - 1, leaf, negated_leaf, iff, negated) for _ in "ab"),
    )
    return negate(node) if negated and rng.random() < negated else node


def expected_false_optional(m, products):
    fs = all_features(m)
    everything = set().union(*products) if products else set()
    out = []
    for name, f in fs.items():
        parent_group = f.eContainer()
        if parent_group is None or not hasattr(parent_group, "kind"):
            continue  # the root
        parent = parent_group.eContainer().name
        kind = parent_group.kind.name
        n = len(parent_group.features)
        lower = {"mandatory": n, "optional": 0, "alternative": 1, "or": 1}.get(
            kind, parent_group.lower
        )
        if kind == "mandatory" or (lower >= 1 and n == 1) or parent not in everything:
            continue
        if all(name in p for p in products if parent in p):
            out.append(name)
    return sorted(out)


@pytest.mark.parametrize("seed", range(60))
def test_random_model_against_brute_force(seed: int) -> None:
    m = random_model(random.Random(seed))
    products = brute_force_products(m)
    names = set(all_features(m))
    with FeatureModelFormula(m) as f:
        assert f.satisfiable() == bool(products)
        assert f.count().value == len(products)
        assert set(f.products()) == set(products)
        if products:
            assert f.core_features() == sorted(set.intersection(*map(set, products)))
            assert f.dead_features() == sorted(names - set().union(*products))
        else:
            assert f.core_features() == [] and f.dead_features() == sorted(names)
        assert f.false_optional_features() == expected_false_optional(m, products)
        # a full product is a complete selection; a non-product is not complete
        for product in products[:3]:
            result = check_selection(f, sorted(product), sorted(names - product))
            assert result.status == "complete" and set(result.features) == product


def iff_heavy_model(rng: random.Random):
    """Five optional features under the root and constraints of nested iffs (with the
    other operators and negations in between), six levels deep."""
    m = model(feature("R", group("optional", *(feature(f"F{i}") for i in range(1, 6)))))
    fs = all_features(m)
    for line in range(rng.randint(1, 2)):
        formula = random_formula(rng, fs, 6, leaf=0.15, negated_leaf=0.3, iff=0.6, negated=0.2)
        m.constraints.append(constraint(formula, 20 + line))
    return m


@pytest.mark.parametrize("seed", range(30))
def test_nested_iffs_against_brute_force(seed: int) -> None:
    # each iff writes its operands twice: nested ones used to grow the CNF as 2**depth
    # (a chain of 257 iffs exhausted the memory); operands holding an iff are now defined
    # variables, which must not change any answer
    m = iff_heavy_model(random.Random(seed))
    products = brute_force_products(m)
    with FeatureModelFormula(m) as f:
        assert f.count().value == len(products)
        assert set(f.products()) == set(products)
        assert sum(1 for _ in f.cnf.clauses) < 2000


def test_a_long_iff_chain_is_encoded_in_linear_size() -> None:
    m = model(feature("R", group("optional", feature("A"), feature("B"), feature("C"))))
    fs = all_features(m)
    chain = ref("A", fs)
    for index in range(200):
        chain = binary("iff", chain, ref("BCA"[index % 3], fs))
    m.constraints.append(constraint(chain, 20))
    products = brute_force_products(m)
    with FeatureModelFormula(m) as f:
        assert f.count().value == len(products) == 4
        assert sum(1 for _ in f.cnf.clauses) < 4000
