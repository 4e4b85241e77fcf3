"""``spl diff``'s classification, witnesses and counts against brute force.

Pairs of small random feature models (the generators of test_analysis_random.py: every
group kind, cardinality bounds, constraints of every operator, and iff-heavy ones whose
encoding needs Tseitin variables), each model's products enumerated over every
assignment by tests/support (no CNF, no SAT). Over the union of the two feature sets a
product is the set of features it selects, so a feature a model lacks is deselected in
its products: comparing the two sets of products is the oracle.
"""

from __future__ import annotations

import random

from hypothesis import given, settings, strategies as st
from test_analysis_random import iff_heavy_model, random_formula, random_model

from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.analysis.operations.edit_classification import ModelEdit

from support.analysis_models import (
    all_features,
    brute_force_products,
    constraint,
    feature,
    group,
    model,
)
from support.hypothesis_budget import examples

EDITS = ("another model", "same model", "constraint added", "constraint removed")


def expected_class(old: set, new: set) -> str:
    return {
        (False, False): "refactoring",
        (False, True): "generalization",
        (True, False): "specialization",
        (True, True): "arbitrary",
    }[(bool(old - new), bool(new - old))]


def check_against_brute_force(old, new) -> None:
    old_products = set(brute_force_products(old))
    new_products = set(brute_force_products(new))
    with ModelEdit(old, new) as edit:
        old_not_new, new_not_old = edit.witnesses()
        removed, added = edit.counts(None)
        assert edit.classification == expected_class(old_products, new_products)
        assert (removed.value, added.value) == (
            len(old_products - new_products),
            len(new_products - old_products),
        )
        if old_products - new_products:
            assert old_not_new is not None
            assert frozenset(old_not_new) in old_products
            assert frozenset(old_not_new) not in new_products
        else:
            assert old_not_new is None
        if new_products - old_products:
            assert new_not_old is not None
            assert frozenset(new_not_old) in new_products
            assert frozenset(new_not_old) not in old_products
        else:
            assert new_not_old is None
        old_names, new_names = set(all_features(old)), set(all_features(new))
        assert edit.added == sorted(new_names - old_names)
        assert edit.removed == sorted(old_names - new_names)


def pair(rng: random.Random, edit: str, iff_heavy: bool):
    """Two versions: the second drawn afresh, or the first again (rebuilt from the same
    seed: a pyecore element belongs to one model) as it is, with one constraint more,
    or with its first constraint removed."""
    make = iff_heavy_model if iff_heavy else random_model
    seed = rng.randrange(2**32)
    old = make(random.Random(seed))
    if edit == "another model":
        return old, make(rng)
    new = make(random.Random(seed))
    if edit == "constraint added":
        formula = random_formula(rng, all_features(new), 2, leaf=0.4, negated_leaf=0.2)
        new.constraints.append(constraint(formula, 40))
    elif edit == "constraint removed" and new.constraints:
        new.constraints.remove(new.constraints[0])
    return old, new


@settings(max_examples=examples(120))
@given(st.randoms(use_true_random=False), st.sampled_from(EDITS), st.booleans())
def test_random_pairs_against_brute_force(rng: random.Random, edit: str, iff_heavy: bool) -> None:
    old, new = pair(rng, edit, iff_heavy)
    check_against_brute_force(old, new)


def cardinality_model(upper: int):
    """R with a [2..upper] group of four: the encoding needs a sequential counter (auxiliary
    variables) for the lower bound."""
    members = [feature(name) for name in "ABCD"]
    return model(feature("R", group("cardinality", *members, lower=2, upper=upper)))


def test_an_equivalent_group_with_auxiliary_variables_is_a_refactoring() -> None:
    # [2..4] and [2..*] over four members mean the same and are written differently, so
    # each version's group is negated rather than shared; negating the counter's clauses
    # one by one would find "violations" by a choice of counter variables alone
    check_against_brute_force(cardinality_model(4), cardinality_model(-1))
    with ModelEdit(cardinality_model(4), cardinality_model(-1)) as edit:
        assert edit.classification == "refactoring"


def test_a_tightened_group_is_a_specialization() -> None:
    with ModelEdit(cardinality_model(-1), cardinality_model(3)) as edit:
        assert edit.classification == "specialization"
        assert edit.witnesses()[0] == ["A", "B", "C", "D", "R"]
        assert edit.counts(None)[0].value == 1


def test_a_feature_under_another_parent_is_moved() -> None:
    old = model(feature("R", group("optional", feature("A", group("optional", feature("B"))))))
    new = model(feature("R", group("optional", feature("A"), feature("B"))))
    check_against_brute_force(old, new)
    with ModelEdit(old, new) as edit:
        assert [(m.feature, m.old_parent, m.new_parent) for m in edit.moved] == [("B", "A", "R")]
        assert edit.classification == "generalization"
        assert edit.witnesses()[1] == ["B", "R"]


def test_both_bounds_of_a_group_with_auxiliary_variables_are_negated() -> None:
    # [1..2] of four is encoded with a counter for its upper bound: NEW rejects the
    # product with no member (below the lower bound) and those with three or four
    old = model(feature("R", group("optional", *(feature(name) for name in "ABCD"))))
    members = [feature(name) for name in "ABCD"]
    new = model(feature("R", group("cardinality", *members, lower=1, upper=2)))
    check_against_brute_force(old, new)
    with ModelEdit(old, new) as edit:
        assert edit.classification == "specialization"
        assert edit.counts(None)[0].value == 1 + 4 + 1


def test_formulas_given_by_the_caller_stay_open() -> None:
    old, new = cardinality_model(-1), cardinality_model(3)
    with FeatureModelFormula(old) as old_formula, FeatureModelFormula(new) as new_formula:
        with ModelEdit(old_formula, new_formula) as edit:
            assert edit.classification == "specialization"
        # 11 products: 6 pairs, 4 triples, all four; the edit closed none of the solvers
        assert old_formula.count(None).value == 11 and old_formula.solver.solve()
        assert new_formula.count(None).value == 10 and new_formula.solver.solve()
