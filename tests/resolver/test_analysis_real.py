"""The real feature models (tests/data/feature-models), checked against flamapy.

flamapy is not a test dependency: its answers were computed once by
``bench/fm_analysis.py --json-out tests/models/analysis/flamapy_results.json`` (flamapy 2.6,
pysat plugin; product counts by its BDD plugin for the small models) and are stored as
fixtures. One difference of definition is normalised here: flamapy also lists as
false-optional the optional children of *dead* parents (``parent and not child`` is
unsatisfiable because the parent never occurs); spl reports those features as dead only.
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

import pytest
from pysat.solvers import Solver

from spl.dsl.interop.formats import load_feature_model
from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.resolution.selection import check_selection

from support.real_models import REAL_MODELS

DATA = REAL_MODELS
FIXTURES = json.loads(
    (Path(__file__).parents[1] / "models" / "analysis" / "flamapy_results.json").read_text()
)["models"]


@functools.cache
def formula_of(name: str) -> FeatureModelFormula:
    """One loaded model and solver per file for the whole module (automotive01 is big)."""
    return FeatureModelFormula(load_feature_model(DATA / name))


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_same_answers_as_flamapy(name: str) -> None:
    formula = formula_of(name)
    expected = FIXTURES[name]
    assert formula.cnf.num_features == expected["features"]
    assert formula.satisfiable() == expected["satisfiable"]
    assert formula.core_features() == expected["core"]
    assert formula.dead_features() == expected["dead"]
    assert formula.false_optional_features() == sorted(
        set(expected["false_optional"]) - set(expected["dead"])
    )


@pytest.mark.parametrize("name", sorted(n for n in FIXTURES if "products" in FIXTURES[n]))
def test_exact_counts_agree_with_flamapys_bdd(name: str) -> None:
    assert formula_of(name).count().value == FIXTURES[name]["products"]


@pytest.mark.parametrize("name", sorted(n for n in FIXTURES if FIXTURES[n]["dead"]))
def test_dead_feature_selection_gets_a_minimal_explanation(name: str) -> None:
    formula = formula_of(name)
    dead = formula.dead_features()
    result = check_selection(formula, [dead[0]])
    assert result.status == "invalid" and result.conflict
    # minimal: without any one of its rules the selection is satisfiable
    cnf = formula.cnf
    for left_out in result.conflict:
        with Solver(name="glucose4") as solver:
            for rule in result.conflict:
                if rule is not left_out:
                    solver.append_formula(cnf.rule_clauses[rule.index])
            assert solver.solve(assumptions=[cnf.var[dead[0]]]), (name, str(left_out))


def test_selection_on_automotive01_completes_by_propagation() -> None:
    formula = formula_of("automotive01.uvl")
    core = formula.core_features()
    product = next(formula.products())
    chosen = sorted(product - set(core))
    result = check_selection(formula, chosen)
    assert result.status == "complete"
    assert set(result.features) == product
    assert set(result.added) == set(core) - set(chosen)
