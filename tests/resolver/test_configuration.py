"""Decision propagation of the configurator (docs/configure.md, "Propagation"): states,
counts and explanations checked against the products themselves, enumerated by brute
force (tests/support/fm_semantics.py) on small models and with the SAT enumerator on
BerkeleyDB, for seeded random decision sequences."""

from __future__ import annotations

import random
from pathlib import Path

import pytest
from pysat.solvers import Solver

from spl.dsl.fm import language as fm
from spl.dsl.interop.formats import load_analysable_model
from spl.resolver.analysis.configuration import Impossible, Propagator
from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.analysis.operations.product_count import count_with_fixed

from support.fm_semantics import products as brute_force_products

ROOT = Path(__file__).resolve().parents[2]
MAPPING_FM = ROOT / "product_lines" / "mapping3d" / "mapping.fm"
SMALL = [
    ROOT / "product_lines" / "mapping3d" / "mapping.fm",
    ROOT / "product_lines" / "orchard" / "orchard.fm",
    ROOT / "product_lines" / "pharmacy" / "pharmacy.fm",
    ROOT / "product_lines" / "data_acquisition" / "data.fm",
    ROOT / "tests" / "models" / "fm" / "all_constructs.fm",
]


def expected_states(products, decisions: dict[str, bool], names) -> tuple[dict, int]:
    """The five states and the count, straight from the products with the decisions."""
    left = [p for p in products if all((n in p) == v for n, v in decisions.items())]
    states = {}
    for name in names:
        if name in decisions:
            states[name] = "selected" if decisions[name] else "deselected"
        elif all(name in p for p in left):
            states[name] = "implied-selected"
        elif not any(name in p for p in left):
            states[name] = "implied-deselected"
        else:
            states[name] = "open"
    return states, len(left)


@pytest.mark.parametrize("path", SMALL, ids=lambda p: p.name)
def test_states_and_counts_are_those_of_the_products_left(path: Path) -> None:
    model = fm.parse_file(path)
    products = brute_force_products(model)
    formula = FeatureModelFormula(model)
    propagator = Propagator(formula)
    names = formula.cnf.names
    rng = random.Random(path.name)
    for _ in range(12):  # random walks: decide open features until none is left
        decisions: dict[str, bool] = {}
        while True:
            propagation = propagator.propagate(decisions)
            states = propagator.states(decisions, propagation)
            want, count = expected_states(products, decisions, names)
            assert states == want, decisions
            assert count_with_fixed(formula, propagation.fixed, None).value == count
            assert propagator.complete(propagation) == (
                frozenset(n for n, s in states.items() if "selected" in s and "de" not in s)
                in products
            )
            opens = [n for n, s in states.items() if s == "open"]
            if not opens:
                break
            decisions[rng.choice(opens)] = rng.random() < 0.5


def test_a_decision_against_an_implied_value_is_impossible_and_says_why() -> None:
    formula = FeatureModelFormula(fm.parse_file(MAPPING_FM))
    propagator = Propagator(formula)
    with pytest.raises(Impossible) as refused:
        propagator.propagate({"AdditionalPC": True, "Roomba": True})
    assert refused.value.lines[0] == "selecting AdditionalPC, Roomba contradicts:"
    assert "Roomba excludes AdditionalPC" in refused.value.lines[1]
    assert "mapping.fm:29:" in refused.value.lines[1]


def test_the_explanation_names_the_rule_with_its_line_and_the_decisions() -> None:
    formula = FeatureModelFormula(fm.parse_file(MAPPING_FM))
    propagator = Propagator(formula)
    why = propagator.why({"AdditionalPC": True}, "Roomba", False)
    assert why[0] == "selecting Roomba contradicts your decisions (selecting AdditionalPC):"
    assert why[1:] == [f"  Roomba excludes AdditionalPC ({ROOT}/product_lines/mapping3d/"
                       "mapping.fm:29:5)"]  # fmt: skip
    core = propagator.why({}, "Mapping", True)
    assert core[0] == "deselecting Mapping contradicts the feature model:"
    assert "root feature" in core[1]


def test_berkeleydb_states_and_counts_agree_with_a_fresh_solver() -> None:
    """BerkeleyDB has 4,080,389,785 products: each state is checked with two calls of a
    solver of its own, the count against the whole model's count first and against
    the products enumerated once few are left."""
    formula = FeatureModelFormula(
        load_analysable_model(ROOT / "tests" / "data" / "feature-models" / "berkeleydb.uvl")
    )
    cnf = formula.cnf
    propagator = Propagator(formula)
    rng = random.Random(31)
    decisions: dict[str, bool] = {}
    with Solver(name="minisat22", bootstrap_with=list(cnf.clauses)) as fresh:
        assert count_with_fixed(formula, propagator.propagate({}).fixed, None).value == (4080389785)
        while True:
            propagation = propagator.propagate(decisions)
            states = propagator.states(decisions, propagation)
            given = [cnf.literal(n, v) for n, v in decisions.items()]
            for name, state in states.items():
                can_select = fresh.solve(assumptions=[*given, cnf.var[name]])
                can_deselect = fresh.solve(assumptions=[*given, -cnf.var[name]])
                if name in decisions:
                    continue
                want = {
                    (True, True): "open",
                    (True, False): "implied-selected",
                    (False, True): "implied-deselected",
                }[(can_select, can_deselect)]
                assert state == want, (name, decisions)
            count = count_with_fixed(formula, propagation.fixed, None).value
            assert count is not None
            if count <= 2000:
                seen = 0
                with Solver(name="minisat22", bootstrap_with=list(cnf.clauses)) as enumerator:
                    while enumerator.solve(assumptions=given):
                        model = enumerator.get_model()[: cnf.num_features]
                        enumerator.add_clause([-lit for lit in model])
                        seen += 1
                assert count == seen
            opens = sorted(n for n, s in states.items() if s == "open")
            if not opens:
                break
            decisions[rng.choice(opens)] = rng.random() < 0.5


def test_undo_returns_the_remembered_answer_and_a_superset_starts_from_it() -> None:
    formula = FeatureModelFormula(fm.parse_file(MAPPING_FM))
    propagator = Propagator(formula)
    first = propagator.propagate({"AdditionalPC": True})
    propagator.propagate({"AdditionalPC": True, "Stereo": True})
    assert propagator.propagate({"AdditionalPC": True}) is first
