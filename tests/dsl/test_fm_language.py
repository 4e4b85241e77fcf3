"""The .fm language: the example of docs/fm.md, every construct, located errors, the printer."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.core.emf_compare import differences
from spl.dsl.fm import language as fm
from spl.dsl.fm.printer import print_model
from spl.dsl.fm.vocabulary import MAX_FORMULA_DEPTH

from support.fm_semantics import products
from support.real_models import REAL_MODELS

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "tests" / "models" / "fm"
SHIPPED_AND_TEST_MODELS = sorted(
    p for p in [*ROOT.glob("product_lines/*/*.fm"), *ROOT.glob("tests/models/**/*.fm")]
)


def groups_of(feature) -> list[tuple[str, list[str]]]:
    return [(g.kind.name, [c.name for c in g.features]) for g in feature.groups]


def features_by_name(model) -> dict:
    return {f.name: f for f in fm.all_features(model)}


def test_spec_example_means_what_the_spec_says() -> None:
    model = fm.parse_file(MODELS / "spec_example.fm")
    assert model.name == "Mapping3D"
    assert fm.summary(model) == "13 features, 2 constraints"
    by_name = features_by_name(model)
    assert groups_of(model.root) == [
        ("mandatory", ["MobileBase", "PerceptionSensor"]),
        ("optional", ["AdditionalPC"]),
        ("mandatory", ["Environment"]),
        ("optional", ["CollaborativeMapping", "Logging"]),
    ]
    assert groups_of(by_name["MobileBase"]) == [("alternative", ["YouBot", "Roomba"])]
    assert by_name["CollaborativeMapping"].sharing.mode.name == "protected"
    rate = by_name["Logging"].attributes[0]
    assert (rate.name, rate.type.name, rate.value) == ("rate", "double", "1.0")
    first, second = (c.formula for c in model.constraints)
    assert first.operator == "excludes"
    assert (first.left.feature.name, first.right.feature.name) == ("Roomba", "Stereo")
    assert second.operator == "requires" and second.right.operator == "or"
    # located on the name, line and column as written
    assert (by_name["Roomba"].srcLine, by_name["Roomba"].srcCol) == (4, 40)
    assert (model.constraints[1].srcLine, model.constraints[1].srcCol) == (18, 5)
    assert len(products(model)) == 40


def test_mapping3d_feature_model_has_12_products() -> None:
    model = fm.parse_file(ROOT / "product_lines" / "mapping3d" / "mapping.fm")
    by_name = features_by_name(model)
    assert model.root.name == "Mapping"
    assert by_name["SharedMap"].sharing.mode.name == "protected"
    assert groups_of(by_name["Environment"]) == [("alternative", ["Room", "Corridor"])]
    assert len(products(model)) == 12
    assert not any({"Roomba", "AdditionalPC"} <= p for p in products(model))


def test_every_construct() -> None:
    model = fm.parse_file(MODELS / "all_constructs.fm")
    by_name = features_by_name(model)
    root = model.root
    assert root.abstract and root.sharing.mode.name == "private"
    assert [(a.name, a.type.name, a.value) for a in root.attributes] == [
        ("mass", "double", "12.0"),
        ("wheels", "int", "4"),
        ("label", "string", 'robot "one"\\x'),
        ("simulated", "bool", "false"),
    ]
    assert [(g.kind.name, g.lower, g.upper) for g in root.groups] == [
        ("mandatory", 0, 0),
        ("optional", 0, 0),
        ("mandatory", 0, 0),
        ("mandatory", 0, 0),
        ("cardinality", 1, -1),
        ("cardinality", 1, 3),
        ("cardinality", 0, 1),
        ("optional", 0, 0),
    ]
    assert groups_of(by_name["Legged"]) == [("or", ["Two", "Four"])]
    assert by_name["Legged"].abstract
    telemetry = by_name["Telemetry"].groups[0]
    assert (telemetry.kind.name, telemetry.lower, telemetry.upper) == ("cardinality", 1, 1)
    formulas = [c.formula for c in model.constraints]
    # not > and > or > => > <=>
    third = formulas[2]
    assert third.operator == "iff" and third.left.operator == "implies"
    assert third.left.left.operator == "or" and third.left.left.left.eClass.name == "Not"
    assert third.left.left.right.operator == "and"
    # implications associate to the right, <=> to the left
    assert formulas[4].right.operator == "implies"
    assert formulas[5].left.operator == "implies"
    assert formulas[6].left.operator == "iff"
    assert formulas[7].right.operator == "iff"


def test_consecutive_children_share_a_group_and_blocks_start_new_ones() -> None:
    model = fm.parse_text(
        "feature model M root R { mandatory A attribute x : int = 1 mandatory B "
        "mandatory { C } mandatory D optional E }"
    )
    assert groups_of(model.root) == [
        ("mandatory", ["A", "B"]),
        ("mandatory", ["C"]),
        ("mandatory", ["D"]),
        ("optional", ["E"]),
    ]


def test_a_group_after_a_name_belongs_to_that_feature() -> None:
    model = fm.parse_text("feature model M root R { optional A xor { B C } }")
    assert groups_of(features_by_name(model)["A"]) == [("alternative", ["B", "C"])]
    model = fm.parse_text("feature model M root R { optional A { } xor { B C } }")
    assert groups_of(model.root) == [("optional", ["A"]), ("alternative", ["B", "C"])]
    text = print_model(model)
    assert "optional A { }" in text
    assert list(differences(model, fm.parse_text(text))) == []


@pytest.mark.parametrize("path", SHIPPED_AND_TEST_MODELS, ids=lambda p: p.name)
def test_printer_round_trips_every_model(path: Path) -> None:
    model = fm.parse_file(path)
    text = print_model(model)
    again = fm.parse_text(text, "printed.fm")
    assert list(differences(model, again)) == []
    assert print_model(again) == text  # canonical: printing is a fixed point


def test_round_trip_keeps_the_product_set() -> None:
    model = fm.parse_file(MODELS / "all_constructs.fm")
    assert products(fm.parse_text(print_model(model))) == products(model)


def error_list(text: str) -> list[tuple[int, int, str]]:
    with pytest.raises(ModelError) as info:
        fm.parse_text(text, "bad.fm")
    return [(d.location.line, d.location.col, d.message) for d in info.value.diagnostics]


def test_semantic_errors_are_all_reported_at_their_names() -> None:
    text = (
        "feature model M\n"  # 1
        "root R {\n"  # 2
        "    optional A\n"  # 3
        "    optional abstract A\n"  # 4
        "    group [3..1] { B C }\n"  # 5
        "    group [0..0] { D }\n"  # 6
        "    optional E {\n"  # 7
        "        attribute n : int = 1.5\n"  # 8
        '        attribute b : bool = "yes"\n'  # 9
        "        attribute d : double = true\n"  # 10
        "        sharing public\n"  # 11
        "        sharing private\n"  # 12
        "    }\n"  # 13
        "}\n"  # 14
        "constraints {\n"  # 15
        "    A requires Nope and (B or Missing)\n"  # 16
        "}\n"
    )
    errors = error_list(text)
    assert [(line, col) for line, col, _ in errors] == [
        (4, 23),
        (5, 5),
        (6, 5),
        (8, 29),
        (9, 30),
        (10, 32),
        (12, 9),
        (16, 16),
        (16, 31),
    ]
    messages = [m for _, _, m in errors]
    assert "duplicate feature A" in messages[0] and "line 3" in messages[0]
    assert "bad cardinality" in messages[1] and "bad cardinality" in messages[2]
    assert "attribute n is int" in messages[3] and "a double" in messages[3]
    assert "attribute b is bool" in messages[4]
    assert "attribute d is double" in messages[5]
    assert "two sharing attributes" in messages[6]
    assert messages[7:] == ["unknown feature Nope", "unknown feature Missing"]


@pytest.mark.parametrize(
    ("text", "line", "col", "expected"),
    [
        ("feature model M\nroot R {\n  optional \n}\n", 4, 1, "feature name"),
        ("feature model M\nroot R { optional Café }\n", 2, 19, "syntax error"),
        ("feature model M\nroot R { optional or }\n", 2, 19, "feature name"),
        ("feature model M\nroot R { }\nconstraints { R and }\n", 3, 21, "syntax error"),
        ("feature model M\nroot R { attribute x : float = 1 }\n", 2, 24, "syntax error"),
        ("feature model M\nroot R { sharing open }\n", 2, 18, "syntax error"),
        ("feature model M\nroot R { xor { } }\n", 2, 16, "feature name"),
    ],
)
def test_syntax_errors_are_located_without_traceback(
    text: str, line: int, col: int, expected: str
) -> None:
    errors = error_list(text)
    assert len(errors) == 1
    assert errors[0][:2] == (line, col)
    assert expected in errors[0][2]
    assert "Traceback" not in errors[0][2]


def test_keywords_are_whole_words() -> None:
    model = fm.parse_text(
        "feature model M root R { optional order optional notable optional android }\n"
        "constraints { order or notable and android }"
    )
    formula = model.constraints[0].formula
    assert formula.operator == "or" and formula.left.feature.name == "order"


def test_comments_are_ignored() -> None:
    model = fm.parse_text("// c\nfeature model M /* x\ny */ root R { optional A // A\n }")
    assert groups_of(model.root) == [("optional", ["A"])]


def test_attribute_names_with_a_meaning_in_the_exchange_formats_are_refused() -> None:
    errors = error_list(
        "feature model M\nroot R {\n  attribute abstract : bool = true\n"
        '  attribute sharing : string = "public"\n  attribute original_name : int = 1\n}\n'
    )
    assert [(line, col) for line, col, _ in errors] == [(3, 3), (4, 3), (5, 3)]
    assert "reserved" in errors[0][2] and "reserved" in errors[1][2]
    assert "string" in errors[2][2]


def test_byte_order_mark_is_accepted(tmp_path: Path) -> None:
    path = tmp_path / "bom.fm"
    path.write_bytes("\ufefffeature model M root R { optional A }".encode())
    assert fm.summary(fm.parse_file(path)) == "2 features, 0 constraints"


REAL = sorted(REAL_MODELS.glob("*.uvl"))


@pytest.mark.parametrize("path", REAL, ids=lambda p: p.stem)
def test_printer_round_trips_the_real_models(path: Path) -> None:
    from spl.dsl.interop.uvl import read_uvl

    model = read_uvl(path)
    assert list(differences(model, fm.parse_text(print_model(model), "printed.fm"))) == []


def test_hostile_nesting_is_a_located_error_not_a_crash() -> None:
    deep_formula = "(" * 5000 + "A" + ")" * 5000
    errors = error_list(f"feature model M root R {{ optional A }} constraints {{ {deep_formula} }}")
    assert errors == [(1, 1, "the model is nested too deeply (features or parentheses)")]
    levels = 60
    reasonable = "feature model M root R { "
    reasonable += "".join(f"optional F{i} {{ " for i in range(levels)) + "}" * (levels + 1)
    assert fm.summary(fm.parse_text(reasonable)) == f"{levels + 1} features, 0 constraints"


def test_spl_check_reports_a_summary_or_every_error(tmp_path: Path) -> None:
    from click.testing import CliRunner

    from spl.cli import main

    result = CliRunner().invoke(main, ["check", str(ROOT / "product_lines/mapping3d/mapping.fm")])
    assert result.exit_code == 0
    assert result.output.strip().endswith("mapping.fm: ok: 12 features, 1 constraint")
    bad = tmp_path / "bad.fm"
    bad.write_text("feature model M\nroot R { optional A optional A }\nconstraints { B }\n")
    result = CliRunner().invoke(main, ["check", str(bad)])
    assert result.exit_code == 1
    assert result.output.splitlines() == [
        f"{bad}:2:30: error: duplicate feature A (first declared at line 2)",
        f"{bad}:3:15: error: unknown feature B",
    ]


@pytest.mark.parametrize(
    ("fm_op", "uvl_op", "xml_tag"),
    [("or", "|", "disj"), ("and", "&", "conj"), ("=>", "=>", None), ("<=>", "<=>", None)],
)
def test_a_constraint_too_deep_for_the_readers_is_refused_by_every_format(
    tmp_path: Path, fm_op: str, uvl_op: str, xml_tag: str | None
) -> None:
    # was: an internal error (RecursionError) from a chain of 900 operators; then a
    # refusal of every chain over 200. A chain of one `and` or `or` is now read whatever
    # its length (balanced); other operators nested that deep are refused, located
    from spl.dsl.interop.featureide import read_featureide
    from spl.dsl.interop.uvl import read_uvl

    too_deep = (
        f"constraint nested 899 operators deep (at most {MAX_FORMULA_DEPTH}, a chain of one "
        "'and' or 'or' counting as a balanced tree): split it into several constraints"
    )
    associative = fm_op in ("or", "and")
    chain = f" {fm_op} ".join(["A", "B"] * 450)
    fm_text = f"feature model M root R {{ optional A optional B }} constraints {{\n  {chain}\n}}"
    uvl = tmp_path / "m.uvl"
    uvl.write_text("features\n\tR\n\t\toptional\n\t\t\tA\n\t\t\tB\nconstraints\n\t"
                   + f" {uvl_op} ".join(["A", "B"] * 450) + "\n")  # fmt: skip
    if associative:
        expected = {frozenset({"R", "A", "B"})} | (
            {frozenset({"R", "A"}), frozenset({"R", "B"})} if fm_op == "or" else set()
        )
        assert products(fm.parse_text(fm_text)) == expected
        assert products(read_uvl(uvl)) == expected
    else:
        assert error_list(fm_text) == [(2, 3, too_deep)]
        with pytest.raises(ModelError) as refused:
            read_uvl(uvl)
        assert [str(d) for d in refused.value.diagnostics] == [f"{uvl}:7:2: error: {too_deep}"]
    if xml_tag is not None:  # FeatureIDE's n-ary <disj>/<conj> are read as chains too
        xml = tmp_path / "m.xml"
        operands = "<var>A</var><var>B</var>" * 450
        xml.write_text(
            '<featureModel><struct><and name="R"><feature name="A"/><feature name="B"/></and>'
            f"</struct><constraints><rule><{xml_tag}>{operands}</{xml_tag}></rule>"
            "</constraints></featureModel>"
        )
        assert products(read_featureide(xml)) == expected


def test_chains_of_thousands_and_deep_parentheses_read_in_uvl(tmp_path: Path) -> None:
    """What the community writes is read: a 5,000-way `|`, the same `&` negated, and a
    pair inside 400 parentheses, and they mean what they say."""
    from spl.dsl.interop.uvl import read_uvl_plain
    from spl.resolver.analysis.formula import FeatureModelFormula

    names = [f"F{i}" for i in range(5000)]
    uvl = tmp_path / "chains.uvl"
    uvl.write_text(
        "features\n\tR\n\t\toptional\n"
        + "".join(f"\t\t\t{name}\n" for name in names)
        + "constraints\n\t"
        + " | ".join(names)
        + "\n\t!("
        + " & ".join(names)
        + ")\n\t"
        + "(" * 400
        + "!F0 | F1 | F0"
        + ")" * 400
        + "\n\t!F4999\n"
    )
    model = read_uvl_plain(uvl)
    assert len(model.constraints) == 4
    with FeatureModelFormula(model) as formula:
        assert formula.satisfiable()
        assert formula.dead_features() == ["F4999"]  # only the unit constraint kills one
        assert formula.core_features() == ["R"]


def test_the_deepest_constraint_allowed_goes_through_every_format(tmp_path: Path) -> None:
    from spl.dsl.interop.featureide import read_featureide
    from spl.dsl.interop.featureide_writer import write_featureide
    from spl.dsl.interop.uvl import read_uvl, write_uvl

    chain = " => ".join(["A", "B"] * (MAX_FORMULA_DEPTH // 2) + ["A"])
    model = fm.parse_text(
        f"feature model M root R {{ optional A optional B }} constraints {{ {chain} }}"
    )
    (tmp_path / "m.uvl").write_text(write_uvl(model))
    (tmp_path / "m.xml").write_bytes(write_featureide(read_uvl(tmp_path / "m.uvl")))
    back = read_featureide(tmp_path / "m.xml")
    constraints = print_model(model).partition("constraints")[2]
    assert chain in constraints
    assert print_model(back).partition("constraints")[2] == constraints
    assert products(back) == products(model)
