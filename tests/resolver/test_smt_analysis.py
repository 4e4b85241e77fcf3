"""Analysis of UVL's Arithmetic and Type levels (typed features, feature cardinalities,
equations) on z3 equals brute-force enumeration (tests/support/fm_typed_semantics.py,
docs/fm.md's semantics), and spl analyze reports it with names as written."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings

from spl.cli import main
from spl.core.diagnostics import ModelError
from spl.dsl.interop.formats import load_line_feature_model
from spl.dsl.interop.uvl_reader import parse_uvl_plain
from spl.dsl.interop.uvl_typed import TypedFeatureModel
from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.analysis.smt import SmtFormula

from support.fm_typed_semantics import analysis, expected_analysis
from support.hypothesis_budget import examples
from support.uvl_typed_models import typed_models


@settings(max_examples=examples(25), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(typed_models())
def test_the_analysis_equals_brute_force(text: str) -> None:
    model = parse_uvl_plain(text, "random.uvl")
    assert isinstance(model, TypedFeatureModel)
    with SmtFormula(model) as formula:
        assert analysis(formula) == expected_analysis(model, formula), text


def test_precedence_and_division_as_arithmetic_writes_them() -> None:
    text = (
        "features\n\tA\n\t\toptional\n\t\t\tB {Price 2, Fun 12}\n\t\t\tC {Price 7, Fun 6}\n"
        "constraints\n\tB.Fun + C.Fun * B.Price == 24\n\tB.Fun / (C.Fun + B.Price) == 1.5\n"
        "\tB.Fun - C.Fun - B.Price == 4\n"
    )
    with SmtFormula(parse_uvl_plain(text, "p.uvl")) as formula:
        assert analysis(formula) == {
            "satisfiable": True,
            "core": ["A", "B", "C"],
            "dead": [],
            "false_optional": ["B", "C"],
            "count": 1,
        }


def test_a_deselected_typed_feature_is_zero_and_cardinality_bounds_instances() -> None:
    # Size > 3 can hold only with Size selected: deselected it is 0
    text = "features\n\tR\n\t\toptional\n\t\t\tInteger Size\nconstraints\n\tSize > 3\n"
    with SmtFormula(parse_uvl_plain(text, "z.uvl")) as formula:
        assert formula.core_features() == ["R", "Size"]
    text = "features\n\tR\n\t\toptional\n\t\t\tA cardinality [2..4]\n"
    model = parse_uvl_plain(text, "c.uvl")
    assert isinstance(model, TypedFeatureModel) and model.cardinalities["A"][:2] == (2, 4)
    with SmtFormula(model) as formula:
        assert formula.count(None).value == 2


def test_spl_analyze_reports_a_typed_model_with_names_as_written(tmp_path: Path) -> None:
    path = tmp_path / "pizza.uvl"
    path.write_text(
        'features\n\t"Pizza+"\n\t\tmandatory\n\t\t\tInteger "Größe"\n\t\toptional\n'
        "\t\t\tCheese {Price 2}\n\t\t\tHam {Price 3}\n"
        'constraints\n\t"Größe" >= 20 & "Größe" <= 40\n\tsum(Price) < 5\n',
        encoding="utf-8",
    )
    result = CliRunner().invoke(main, ["analyze", "--json", "--count", str(path)])
    assert result.exit_code == 0, result.output
    report = json.loads(result.output)
    assert report["core"] == ["Größe", "Pizza+"]
    assert (report["products"], report["constraints"], report["satisfiable"]) == (3, 2, True)
    converted = CliRunner().invoke(main, ["convert", str(path), str(tmp_path / "p.fm")])
    assert converted.exit_code == 1
    assert f"{path}:4:12: error: typed feature Größe (Integer): spl convert to" in converted.output
    assert not (tmp_path / "p.fm").exists()


def test_check_reads_a_typed_model_and_a_product_line_refuses_it(tmp_path: Path) -> None:
    path = tmp_path / "sized.uvl"
    path.write_text("features\n\tR\n\t\toptional\n\t\t\tInteger Size\nconstraints\n\tSize > 3\n")
    checked = CliRunner().invoke(main, ["check", str(path)])
    assert checked.exit_code == 0, checked.output
    with pytest.raises(ModelError) as refused:
        load_line_feature_model(path)
    assert [str(d) for d in refused.value.diagnostics] == [
        f"{path}:4:12: error: typed feature Size (Integer): a product line's feature model "
        "carries the Boolean level of UVL only (spl analyze reads the Arithmetic and Type "
        "levels, docs/fm.md)"
    ]


def test_an_imported_typed_model_joins_with_its_equations(tmp_path: Path) -> None:
    (tmp_path / "sub.uvl").write_text(
        "features\n\tS\n\t\toptional\n\t\t\tString T\n\t\t\tInteger N\n\t\t\tB {Price 2}\n"
        "constraints\n\tN + B.Price * 2 > sum(Price) & !(N / 2 == 1)\n"
        "\tavg(Price, S) >= 0 | len(T) == 2\n"
    )
    main_file = tmp_path / "main.uvl"
    main_file.write_text(
        "imports\n\tsub as s\nfeatures\n\tR\n\t\tmandatory\n\t\t\ts.S\nconstraints\n\ts.N < 10\n"
    )
    model = parse_uvl_plain(main_file.read_text(), str(main_file))
    assert isinstance(model, TypedFeatureModel) and len(model.equations) == 3
    with SmtFormula(model) as formula:
        # B, or else T (avg over no B divides by zero) with N positive and not 2
        assert formula.core_features() == ["R", "s_S"]
        assert formula.count(None).value == 5


def test_a_chain_of_thousands_of_operators_is_read_and_analysed() -> None:
    terms = " + ".join(["A.Price"] * 5000)
    alternatives = " | ".join(["A > 0"] * 3000)
    text = (
        "features\n\tR\n\t\toptional\n\t\t\tA {Price 1}\n"
        f"constraints\n\t{terms} > 3\n\t{alternatives}\n"
    )
    with SmtFormula(parse_uvl_plain(text, "long.uvl")) as formula:
        assert formula.core_features() == ["A", "R"]


def test_the_sat_only_commands_refuse_a_typed_model_rather_than_drop_its_equations(
    tmp_path: Path,
) -> None:
    path = tmp_path / "sized.uvl"
    path.write_text("features\n\tR\n\t\toptional\n\t\t\tInteger Size\nconstraints\n\tSize > 3\n")
    for command in (["products", str(path)], ["diff", str(path), str(path)]):
        result = CliRunner().invoke(main, command)
        assert result.exit_code == 1, result.output
        assert f"{path}:4:12: error: typed feature Size (Integer): this command reads" in (
            result.output
        )


def test_a_boolean_model_on_z3_gets_the_answers_of_sat() -> None:
    """A true equation sends a community model to z3: the same core, dead and
    false-optional features as the SAT path."""
    path = Path(__file__).parents[1] / "data" / "feature-models" / "berkeleydb.uvl"
    text = path.read_text(encoding="utf-8").rstrip("\n") + "\n\t1 + 1 == 2\n"
    typed = parse_uvl_plain(text, str(path))
    assert isinstance(typed, TypedFeatureModel)
    with SmtFormula(typed) as smt, FeatureModelFormula(parse_uvl_plain(path.read_text())) as sat:
        assert smt.core_features() == sat.core_features()
        assert smt.dead_features() == sat.dead_features()
        assert smt.false_optional_features() == sat.false_optional_features()


@pytest.mark.parametrize(
    ("entry", "equation", "where", "message"),
    [
        ("A cardinality [5..2]", "A", "4:18", "bad feature cardinality [5..2]"),
        ("String A", "A + 1 > 2", "6:2", "expected a number here, got a string"),
        (
            "A {Price 1}",
            "A.Price < 'x'",
            "6:10",
            "< compares two numbers or two strings, not a number and a string",
        ),
        ("String A", "A < 'x'", "6:4", "strings compare with == and != only, not <"),
        ("A", "sum(Price) > 1", "6:2", "no feature has a number attribute Price"),
        ("A", "B.Price > 1", "6:2", "unknown feature or attribute B.Price"),
        ("A", "len(3) == 1", "6:6", "expected a name, got 3"),
    ],
)
def test_a_bad_typed_part_is_refused_located(
    entry: str, equation: str, where: str, message: str
) -> None:
    text = f"features\n\tR\n\t\toptional\n\t\t\t{entry}\nconstraints\n\t{equation}\n"
    with pytest.raises(ModelError) as refused:
        parse_uvl_plain(text, "bad.uvl")
    assert [str(d) for d in refused.value.diagnostics] == [f"bad.uvl:{where}: error: {message}"]
