"""Every analysis result on the vendored corpus stays what it was before the speed work.

``tests/models/analysis/spl_results.json`` holds spl's own answers (features, constraints,
satisfiable, core, dead, false-optional, exact product count) for every file of
tests/data/feature-models, computed with the code as it was *before* the UVL reader
and ``spl analyze`` were rewritten for speed. Any later change of reader,
encoding or analysis that alters one of these answers fails here.

Each model is checked both through the library (``load_feature_model`` and
:class:`FeatureModelFormula`, as ``spl products`` and the resolver use it) and through
``spl analyze --json --count`` (the command's own, faster reading path).
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from spl.cli import main
from spl.dsl.interop.formats import load_feature_model
from spl.resolver.analysis.formula import FeatureModelFormula

from support.real_models import REAL_MODELS

PINNED = json.loads(
    (Path(__file__).parents[1] / "models" / "analysis" / "spl_results.json").read_text()
)["models"]


def test_every_vendored_model_is_pinned() -> None:
    vendored = {p.name for p in REAL_MODELS.iterdir() if p.suffix in (".uvl", ".xml")}
    assert vendored == set(PINNED)


@functools.cache
def library_answers(name: str) -> dict:
    model = load_feature_model(REAL_MODELS / name)
    with FeatureModelFormula(model) as formula:
        return {
            "features": formula.cnf.num_features,
            "constraints": len(model.constraints),
            "satisfiable": formula.satisfiable(),
            "core": formula.core_features(),
            "dead": formula.dead_features(),
            "false_optional": formula.false_optional_features(),
            "products": formula.count(600).value,
        }


@pytest.mark.parametrize("name", sorted(PINNED))
def test_library_answers_are_the_pinned_ones(name: str) -> None:
    assert library_answers(name) == PINNED[name]


@pytest.mark.parametrize("name", sorted(PINNED))
def test_analyze_command_answers_are_the_pinned_ones(name: str) -> None:
    result = CliRunner().invoke(main, ["analyze", str(REAL_MODELS / name), "--json", "--count"])
    assert result.exit_code == 0, result.output
    report = json.loads(result.output)
    expected = PINNED[name]
    assert {key: report[key] for key in expected} == expected
    assert report["products_note"] == ""
