"""Analysis operations on small hand-made models with known answers.

Every count is checked against an independent brute-force evaluator of the feature-model
semantics (tests/analysis_models.py), which never goes through the CNF or a SAT solver.
"""

from __future__ import annotations

import pytest

from spl.dsl.fm.printer import format_formula
from spl.resolver.analysis.cnf import encode
from spl.resolver.analysis.formula import (
    FeatureModelFormula,
    core_features,
    count_products,
    dead_features,
    enumerate_products,
    false_optional_features,
    is_satisfiable,
)

from support.analysis_models import (
    binary,
    brute_force_products,
    constraint,
    feature,
    group,
    mapping3d,
    model,
    negate,
    ref,
)


def fs_of(m):
    from support.analysis_models import all_features

    return all_features(m)


def test_mapping3d_core_count_and_products_match_brute_force() -> None:
    m, _ = mapping3d()
    with FeatureModelFormula(m) as f:
        assert f.satisfiable()
        assert f.core_features() == ["Environment", "Mapping", "MobileBase", "PerceptionSensor"]
        assert f.dead_features() == []
        assert f.false_optional_features() == []
        expected = set(brute_force_products(m))
        assert f.count().value == len(expected) == 40
        assert set(f.products()) == expected


def test_void_model_has_no_product_and_every_feature_dead() -> None:
    root = feature("R", group("mandatory", feature("A"), feature("B")))
    m = model(root)
    fs = fs_of(m)
    m.constraints.append(constraint(binary("excludes", ref("A", fs), ref("B", fs)), 9))
    assert not is_satisfiable(m)
    assert core_features(m) == []
    assert dead_features(m) == ["A", "B", "R"]
    assert false_optional_features(m) == []
    assert count_products(m).value == 0
    assert list(enumerate_products(m)) == []


def test_dead_feature_through_an_excludes() -> None:
    root = feature(
        "R",
        group("mandatory", feature("A")),
        group("optional", feature("B", group("optional", feature("C")))),
    )
    m = model(root)
    fs = fs_of(m)
    m.constraints.append(constraint(binary("excludes", ref("A", fs), ref("B", fs)), 9))
    assert dead_features(m) == ["B", "C"]
    assert core_features(m) == ["A", "R"]
    assert count_products(m).value == len(brute_force_products(m)) == 1


def test_false_optional_through_a_requires() -> None:
    root = feature(
        "R",
        group("mandatory", feature("A")),
        group("optional", feature("B"), feature("C", group("optional", feature("D")))),
    )
    m = model(root)
    fs = fs_of(m)
    m.constraints.append(constraint(binary("requires", ref("A", fs), ref("B", fs)), 9))
    m.constraints.append(constraint(binary("requires", ref("C", fs), ref("D", fs)), 10))
    with FeatureModelFormula(m) as f:
        # B is core (A is), so every product with R has it; D whenever its parent C
        assert f.false_optional_features() == ["B", "D"]
        assert f.core_features() == ["A", "B", "R"]
        assert f.dead_features() == []
        assert f.count().value == len(brute_force_products(m)) == 2


def test_children_of_a_dead_parent_are_dead_not_false_optional() -> None:
    root = feature("R", group("optional", feature("P", group("optional", feature("Q")))))
    m = model(root)
    fs = fs_of(m)
    m.constraints.append(constraint(negate(ref("P", fs)), 9))
    m.constraints.append(constraint(binary("implies", ref("P", fs), ref("Q", fs)), 10))
    assert dead_features(m) == ["P", "Q"]
    assert false_optional_features(m) == []


@pytest.mark.parametrize(
    ("lower", "upper"), [(0, 1), (1, 2), (2, 3), (2, -1), (3, 3), (0, 0), (4, 4), (2, 5)]
)
def test_cardinality_groups_count_like_brute_force(lower: int, upper: int) -> None:
    root = feature(
        "R",
        group(
            "cardinality",
            feature("A"),
            feature("B"),
            feature("C"),
            feature("D", group("or", feature("E"), feature("F"))),
            lower=lower,
            upper=upper,
        ),
    )
    m = model(root)
    expected = set(brute_force_products(m))
    with FeatureModelFormula(m) as f:
        assert f.count().value == len(expected)
        assert set(f.products()) == expected
        assert f.satisfiable() == bool(expected)
        everything = set().union(*expected) if expected else set()
        assert f.dead_features() == sorted(set(fs_of(m)) - everything)


def test_large_alternative_uses_a_counter_encoding_and_still_counts_exactly() -> None:
    members = [feature(f"X{i}") for i in range(15)]
    root = feature("R", group("alternative", *members), group("optional", feature("Y")))
    m = model(root)
    fs = fs_of(m)
    m.constraints.append(
        constraint(binary("requires", ref("Y", fs), binary("or", ref("X1", fs), ref("X2", fs))), 9)
    )
    cnf = encode(m)
    assert cnf.num_vars > cnf.num_features  # auxiliary variables: the count is projected
    assert count_products(m).value == 15 + 2
    assert len(list(enumerate_products(m))) == 17


def test_arbitrary_formulas_go_through_tseitin_and_count_like_brute_force() -> None:
    names = ["A", "B", "C", "D", "E", "G"]
    root = feature("R", group("optional", *[feature(n) for n in names]))
    m = model(root)
    fs = fs_of(m)

    def r(n):
        return ref(n, fs)

    # (A <=> B) <=> (C <=> (D and not E)) or G : large when distributed -> Tseitin
    inner = binary("iff", r("C"), binary("and", r("D"), negate(r("E"))))
    big = binary("or", binary("iff", binary("iff", r("A"), r("B")), inner), r("G"))
    m.constraints.append(constraint(big, 9))
    m.constraints.append(constraint(negate(binary("and", r("A"), r("G"))), 10))
    expected = set(brute_force_products(m))
    assert count_products(m).value == len(expected)
    assert set(enumerate_products(m)) == expected
    assert encode(m).num_vars > encode(m).num_features  # Tseitin definitions were used
    assert format_formula(big) == "((A <=> B) <=> (C <=> D and not E)) or G"


def test_count_reports_unknown_instead_of_guessing_when_the_bound_is_hit() -> None:
    members = [feature(f"X{i}", group("or", feature(f"Y{i}"), feature(f"Z{i}"))) for i in range(40)]
    root = feature("R", group("optional", *members))
    m = model(root)
    fs = fs_of(m)
    for i in range(39):  # a chain so the model does not fall apart into components
        m.constraints.append(
            constraint(
                binary(
                    "or",
                    binary("implies", ref(f"Y{i}", fs), ref(f"Z{i + 1}", fs)),
                    ref(f"Y{i + 1}", fs),
                ),
                10 + i,
            )
        )
    with FeatureModelFormula(m) as f:
        unknown = f.count(seconds=0.0)
        assert unknown.value is None and "count skipped" in unknown.note
        assert f.count(seconds=30.0).value is not None


def test_queries_reuse_one_solver_and_agree_with_fresh_ones() -> None:
    m, _ = mapping3d()
    with FeatureModelFormula(m) as f:
        first = (f.core_features(), f.dead_features(), f.false_optional_features())
        assert (f.core_features(), f.dead_features(), f.false_optional_features()) == first
    assert (core_features(m), dead_features(m), false_optional_features(m)) == first


def test_two_literal_constraints_on_one_feature() -> None:
    root = feature("R", group("optional", feature("A"), feature("B"), feature("C")))
    m = model(root)
    fs = fs_of(m)
    m.constraints.append(constraint(binary("requires", ref("A", fs), ref("A", fs)), 9))  # no-op
    m.constraints.append(constraint(binary("excludes", ref("B", fs), ref("B", fs)), 10))  # B dead
    m.constraints.append(constraint(binary("or", ref("C", fs), ref("C", fs)), 11))  # C core
    assert dead_features(m) == ["B"]
    assert core_features(m) == ["C", "R"]
    assert count_products(m).value == len(brute_force_products(m)) == 2


def test_duplicate_names_and_dangling_references_are_located_errors() -> None:
    from spl.core.diagnostics import ModelError

    twice = model(feature("R", group("optional", feature("A", line=2), feature("A", line=3))))
    with pytest.raises(ModelError) as caught:
        encode(twice)
    assert [str(d) for d in caught.value.diagnostics] == [
        "mapping.fm:3:5: error: feature A is defined twice"
    ]
    m = model(feature("R", group("optional", feature("A"))))
    stranger = feature("Stranger")  # in no tree
    c = constraint(
        binary("requires", ref("A", fs_of(m)), ref("Stranger", {"Stranger": stranger})), 7
    )
    m.constraints.append(c)
    with pytest.raises(ModelError) as caught:
        encode(m)
    assert str(caught.value.diagnostics[0]) == (
        "mapping.fm:7:5: error: constraint A requires Stranger names Stranger, "
        "which is not a feature of the tree"
    )
