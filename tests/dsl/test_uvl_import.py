"""UVL import/export over the real community models and small hand-written files."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.core.emf_compare import differences
from spl.dsl.fm import language as fm
from spl.dsl.interop.interchange import ORIGINAL_NAME, original_name
from spl.dsl.interop.uvl import parse_uvl, read_uvl, write_uvl

from support.real_models import REAL_MODELS

# the shared data folder sits next to the working tree
DATA = REAL_MODELS
REAL = sorted(DATA.glob("*.uvl"))
SIZES = {
    "automotive01": 2513,
    "axTLS": 96,
    "berkeleydb": 76,
    "busybox_2010-05-02_14-17-07": 631,
}


def test_every_real_model_is_found() -> None:
    assert sorted(p.stem for p in REAL) == sorted(SIZES)


@pytest.mark.parametrize("path", REAL, ids=[p.stem for p in REAL])
def test_real_uvl_imports_and_round_trips(path: Path) -> None:
    model = read_uvl(path)
    features = list(fm.all_features(model))
    assert len(features) == SIZES[path.stem]
    names = [f.name for f in features]
    assert len(set(names)) == len(names)
    assert all(fm.is_feature_name(n) for n in names)
    again = parse_uvl(write_uvl(model), "export.uvl")
    assert list(differences(model, again)) == []


def test_berkeleydb_structure() -> None:
    model = read_uvl(DATA / "berkeleydb.uvl")
    assert model.root.name == "BerkeleyDb" and model.root.abstract
    by_name = {f.name: f for f in fm.all_features(model)}
    fio = by_name["FIOFeature"]
    assert [(g.kind.name, [c.name for c in g.features]) for g in fio.groups] == [
        ("alternative", ["NIO", "IO"])
    ]
    assert not by_name["featureIO"].abstract
    assert len(model.constraints) == 20
    first = model.constraints[0].formula
    assert first.operator == "implies" and first.right.feature.name == "featureMemoryBudget"
    assert first.srcLine == 119


UVL_ODD = """namespace "my model"

features
    "Root feature" {abstract}
        mandatory
            "a-b"
            a_b
            "or"
        optional
            "1st" {cost 3, weight 1.5, label 'x y', on, abstract false, sharing 'public'}
        [1..*]
            C
            D
        [2]
            E
            F
        alternative
            G
constraints
    "a-b" => !"1st" & (C | D)
    // a comment
    G <=> ("or"
        | E)
"""


def test_names_are_sanitised_injectively_and_written_back() -> None:
    model = parse_uvl(UVL_ODD, "odd.uvl")
    assert model.name == "my_model"
    names = [f.name for f in fm.all_features(model)]
    assert names == ["Root_feature", "a_b_2", "a_b", "or_", "_1st", "C", "D", "E", "F", "G"]
    by_name = {f.name: f for f in fm.all_features(model)}
    assert original_name(by_name["a_b_2"]) == "a-b"
    assert original_name(by_name["a_b"]) == "a_b"
    assert ORIGINAL_NAME not in [a.name for a in by_name["a_b"].attributes]
    first = by_name["_1st"]
    assert [(a.name, a.type.name, a.value) for a in first.attributes] == [
        (ORIGINAL_NAME, "string", "1st"),
        ("cost", "int", "3"),
        ("weight", "double", "1.5"),
        ("label", "string", "x y"),
        ("on", "bool", "true"),
    ]
    assert first.sharing.mode.name == "public" and not first.abstract
    groups = by_name["Root_feature"].groups
    assert [(g.kind.name, g.lower, g.upper) for g in groups[2:4]] == [
        ("cardinality", 1, -1),
        ("cardinality", 2, 2),
    ]
    second = model.constraints[1].formula
    assert second.operator == "iff" and second.right.operator == "or"
    text = write_uvl(model)
    assert '"a-b"' in text and '"1st" {cost 3' in text and '"or"' in text
    again = parse_uvl(text, "again.uvl")
    assert list(differences(model, again)) == []


def test_names_uvl_cannot_quote_are_reported_on_export() -> None:
    # a quoted UVL name holds no dot; FeatureIDE names may, and reach the writer so
    model = parse_uvl('features\n\tR\n\t\toptional\n\t\t\t"x y"\n\t\t\t"_z"\n', "dots.uvl")
    assert [f.name for f in fm.all_features(model)] == ["R", "x_y", "_z"]
    (kept,) = model.root.groups[0].features[0].attributes
    kept.value = "x.y"
    with pytest.raises(ModelError) as info:
        write_uvl(model)
    (problem,) = info.value.diagnostics
    assert (problem.location.line, problem.location.col) == (4, 4)
    assert "'x.y' cannot be written in UVL" in problem.message


def test_uvl_tokens_follow_the_uvl_grammar() -> None:
    model = fm.parse_text(
        "feature model M root R { optional _x { attribute w : double = 0.00001 } "
        "optional Type optional ok_1 }"
    )
    text = write_uvl(model)
    # ID_STRICT starts with a letter; FLOAT has no exponent; keywords are quoted
    assert '"_x" {w 0.00001}' in text and '"Type"' in text and "\t\t\tok_1\n" in text
    assert list(differences(model, parse_uvl(text, "M.uvl"))) == []


def test_constraint_precedence() -> None:
    text = (
        "features\n\tR\n\t\toptional\n\t\t\tA\n\t\t\tB\n\t\t\tC\n"
        "constraints\n\tA | B & !C => A <=> B\n"
    )
    formula = parse_uvl(text).constraints[0].formula
    assert formula.operator == "iff"
    implication = formula.left
    assert implication.operator == "implies"
    assert implication.left.operator == "or"
    assert implication.left.right.operator == "and"
    assert implication.left.right.right.eClass.name == "Not"


@pytest.mark.parametrize(
    ("text", "line", "col", "message"),
    [
        (
            "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tA => Nope\n",
            6,
            7,
            "unknown feature Nope",
        ),
        ("features\n\tR\n\t\tsometimes\n\t\t\tA\n", 3, 3, "expected a group"),
        ("features\n\tR\n\t\t[3..1]\n\t\t\tA\n", 3, 3, "bad cardinality"),
        ("features\n\tR\n\t\toptional\n\t\t\tA\n\t\t\tA\n", 5, 4, "duplicate feature A"),
        (
            "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tA > 'a'\n",
            6,
            4,
            "two numbers or two strings",
        ),
        ("imports\n\tx\nfeatures\n\tR\n", 2, 2, "imported model x not found"),
        ("include\n\tTyped\nfeatures\n\tR\n", 2, 2, "expected a language level"),
        ("features\n\tR {abstract maybe}\n", 2, 14, "abstract takes true or false"),
    ],
)
def test_located_errors(text: str, line: int, col: int, message: str) -> None:
    with pytest.raises(ModelError) as info:
        parse_uvl(text, "bad.uvl")
    found = [(d.location.line, d.location.col, d.message) for d in info.value.diagnostics]
    assert any((ln, c) == (line, col) and message in m for ln, c, m in found), found


def test_all_errors_reported_at_once() -> None:
    text = "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tA => X\n\tY | A\n"
    with pytest.raises(ModelError) as info:
        parse_uvl(text, "bad.uvl")
    assert [d.location.line for d in info.value.diagnostics] == [6, 7]


def test_hostile_nesting_is_a_located_error() -> None:
    deep = "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\t" + "!" * 5000 + "A\n"
    with pytest.raises(ModelError) as info:
        parse_uvl(deep, "deep.uvl")
    assert [str(d) for d in info.value.diagnostics] == [
        "deep.uvl:6:2: error: constraint nested 5000 operators deep (at most 200, a chain of "
        "one 'and' or 'or' counting as a balanced tree): split it into several constraints"
    ]


def test_identifiers_uvl_reserves_are_quoted_and_read_back() -> None:
    text = 'namespace "features"\nfeatures\n\tR {"_k" 1, sharing \'public\'}\n'
    model = parse_uvl(text, "q.uvl")
    assert model.name == "features"
    assert [(a.name, a.value) for a in model.root.attributes] == [("_k", "1")]
    text = write_uvl(model)
    assert text.startswith('namespace "features"\n') and '{"_k" 1, sharing' in text
    assert list(differences(model, parse_uvl(text, "q.uvl"))) == []


@pytest.mark.parametrize("attributes", ["{sharing 3}", "{sharing}", "{sharing 'open'}"])
def test_sharing_must_be_a_mode(attributes: str) -> None:
    with pytest.raises(ModelError, match="sharing must be one of public, protected, private"):
        parse_uvl(f"features\n\tR {attributes}\n", "s.uvl")
