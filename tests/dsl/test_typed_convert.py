"""``spl convert`` of typed UVL models keeps what each target carries (docs/fm.md,
"Conversion"): to UVL every language level, composition kept as submodels, read back
to the same model with the same analysis answers; to .fm and FeatureIDE XML a typed
part is refused, located at the first one, and nothing is written."""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from test_uvl_conformance import reference_accepts_text

from spl.cli import main
from spl.core.diagnostics import ModelError
from spl.dsl.fm.plain import FeatureModel
from spl.dsl.interop.formats import converted_files
from spl.dsl.interop.interchange import written_names
from spl.dsl.interop.uvl import read_uvl_plain
from spl.dsl.interop.uvl_typed import TypedFeatureModel
from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.analysis.smt import SmtFormula

from support.fm_typed_semantics import analysis
from support.hypothesis_budget import examples
from support.uvl_typed_models import typed_models

CORPUS = Path(__file__).parents[1] / "data" / "uvl-parser" / "test_models"
VALID = [
    path
    for path in sorted(CORPUS.rglob("*.uvl"))
    if path.relative_to(CORPUS).parts[0] != "faulty"
    and str(path.relative_to(CORPUS)) != "lexing/dotinfeaturename.uvl"
]


def convert(source: Path, target: Path) -> Any:
    result = CliRunner().invoke(main, ["convert", str(source), str(target)])
    return result


def answers(model: FeatureModel) -> dict[str, object]:
    """The analysis answers, features named as written."""
    written = written_names(model)
    typed = isinstance(model, TypedFeatureModel)
    with SmtFormula(model) if typed else FeatureModelFormula(model) as formula:  # type: ignore[arg-type]
        return {
            "satisfiable": formula.satisfiable(),
            "core": sorted(written[name] for name in formula.core_features()),
            "dead": sorted(written[name] for name in formula.dead_features()),
            "false_optional": sorted(written[n] for n in formula.false_optional_features()),
        }


def normal(tree: tuple, written: dict[str, str]) -> tuple:
    """A constraint's tree without positions, features by their written names."""
    head = tree[0]
    if head in ("ref", "value", "selected"):
        return (head, written[tree[1]])
    if head == "attr":
        return ("attr", written[tree[1]], *tree[2:5])
    if head in ("num", "str"):
        return tree[:2]
    if head in ("sum", "avg"):
        return (head, tuple((written[f], normal(v, written)) for f, v in tree[1]))
    return tuple(normal(p, written) if isinstance(p, tuple) else p for p in tree[:-1])


def shape(model: FeatureModel) -> dict[str, object]:
    """Everything a conversion must keep, by written names."""
    written = written_names(model)
    typed = model if isinstance(model, TypedFeatureModel) else None
    return {
        "name": model.written_name,
        "tree": tree(model, written),
        "constraints": sorted(repr(normal(c.formula, written)) for c in model.constraints),
        "types": sorted((written[n], k) for n, k in typed.types.items()) if typed else [],
        "cardinalities": sorted(
            (written[n], lower, upper) for n, (lower, upper, _) in typed.cardinalities.items()
        )
        if typed
        else [],
        "equations": sorted(repr(normal(e.formula, written)) for e in typed.equations)
        if typed
        else [],
    }


def tree(model: FeatureModel, written: dict[str, str]) -> list[tuple]:
    """Each feature in pre-order with its attributes and groups, by written names."""
    found: list[tuple] = []
    stack = [model.root] if model.root is not None else []
    while stack:
        feature = stack.pop()
        attributes = sorted(
            (a.name, a.type, a.value) for a in feature.attributes if a.name != "original_name"
        )
        groups = [
            (g.kind, g.lower, g.upper, [written[c.name] for c in g.features])
            for g in feature.groups
        ]
        found.append((written[feature.name], feature.abstract, attributes, groups))
        stack.extend(reversed([c for g in feature.groups for c in g.features]))
    return found


@pytest.mark.parametrize("path", VALID, ids=[str(p.relative_to(CORPUS)) for p in VALID])
def test_every_valid_parser_model_converts_to_uvl_and_reads_back_the_same(
    path: Path, tmp_path: Path
) -> None:
    target = tmp_path / path.name
    result = convert(path, target)
    assert result.exit_code == 0, result.output
    original, again = read_uvl_plain(path), read_uvl_plain(target)
    assert shape(again) == shape(original)  # the same tree and constraints: the same model
    if isinstance(original, TypedFeatureModel):  # and what z3 answers of it
        assert answers(again) == answers(original)
    # and the UVL project's grammar reads each file (but the five 80 KB generated Boolean
    # models, on which its Python parser takes seconds each: the other models hold every
    # construct the writer emits)
    if path.parent.name != "generated":
        for written in tmp_path.rglob("*.uvl"):
            assert reference_accepts_text(written.read_text(encoding="utf-8")), written
    once = target.read_bytes()  # converting the output again changes no byte
    (tmp_path / "twice").mkdir()
    assert convert(target, tmp_path / "twice" / path.name).exit_code == 0
    assert (tmp_path / "twice" / path.name).read_bytes() == once


@settings(max_examples=examples(25), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(typed_models())
def test_a_random_typed_model_converts_to_uvl_with_the_same_answers(text: str) -> None:
    with tempfile.TemporaryDirectory() as folder:
        source, target = Path(folder) / "random.uvl", Path(folder) / "converted.uvl"
        source.write_text(text, encoding="utf-8")
        _, files = converted_files(source, target)
        target.write_bytes(files[target][1])
        assert reference_accepts_text(target.read_text(encoding="utf-8")), text
        original, again = read_uvl_plain(source), read_uvl_plain(target)
        assert shape(again) == shape(original), text
        assert isinstance(original, TypedFeatureModel) and isinstance(again, TypedFeatureModel)
        with SmtFormula(original) as before, SmtFormula(again) as after:
            assert analysis(after) == analysis(before), text


def test_names_types_and_levels_are_written_as_the_file_has_them(tmp_path: Path) -> None:
    source = tmp_path / "pizza.uvl"
    source.write_text(
        'namespace "Pizza Shop"\nfeatures\n\t"Pizza+"\n\t\tmandatory\n\t\t\tInteger "Größe"\n'
        '\t\toptional\n\t\t\t"2nd Cheese" cardinality [1..*] {Price 2}\n'
        "\t\t\tHam {Price 3.5, Tags ['x', 'y']}\n"
        'constraints\n\t"Größe" >= 20 & "Größe" <= 40\n\tsum(Price) < 5\n'
        '\t!("2nd Cheese".Price > 1) | Ham\n',
        encoding="utf-8",
    )
    result = convert(source, tmp_path / "out.uvl")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "out.uvl").read_text(encoding="utf-8") == (
        'namespace "Pizza Shop"\n\ninclude\n\tBoolean\n\tArithmetic\n'
        "\tArithmetic.feature-cardinality\n\tArithmetic.aggregate-function\n\tType\n\n"
        'features\n\t"Pizza+"\n\t\tmandatory\n\t\t\tInteger "Größe"\n\t\toptional\n'
        '\t\t\t"2nd Cheese" cardinality [1..*] {Price 2}\n'
        "\t\t\tHam {Price 3.5, Tags ['x', 'y']}\n\n"
        'constraints\n\t"Größe" >= 20 & "Größe" <= 40\n\tsum(Price) < 5\n'
        '\t!("2nd Cheese".Price > 1) | Ham\n'
    )


def test_an_aggregate_comes_back_as_the_scope_the_reader_expanded(tmp_path: Path) -> None:
    source = tmp_path / "scopes.uvl"
    source.write_text(
        "features\n\tR\n\t\toptional\n\t\t\tA {Price 1}\n\t\t\t\toptional\n"
        '\t\t\t\t\tA1 {Price 2}\n\t\t\tB {Price 4, "My Price" 2}\n\t\t\tC {"My Price" 3}\n'
        "constraints\n\tsum(Price, A) < 3\n\tavg(A.Price) == 1 | sum(B, C) > 1\n"
        '\tsum("My Price") > 4 => avg("My Price") < 3\n',
        encoding="utf-8",
    )
    target = tmp_path / "out.uvl"
    assert convert(source, target).exit_code == 0
    written = target.read_text(encoding="utf-8")
    assert "\tsum(Price, A) < 3\n\tavg(A.Price) == 1 | sum(B, C) > 1\n" in written
    # an attribute name kept as written has no scope spl can name: spelled out, the same
    assert '(B."My Price" + C."My Price") > 4 => (B."My Price" + C."My Price") / (B + C) < 3' in (
        written
    )
    original, again = read_uvl_plain(source), read_uvl_plain(target)
    assert isinstance(original, TypedFeatureModel) and isinstance(again, TypedFeatureModel)
    with SmtFormula(original) as before, SmtFormula(again) as after:
        assert analysis(after) == analysis(before)


def test_a_chain_of_thousands_of_operators_converts(tmp_path: Path) -> None:
    source = tmp_path / "long.uvl"
    terms = " + ".join(["A.Price"] * 5000)
    alternatives = " | ".join(["A > 0"] * 3000)
    source.write_text(
        f"features\n\tR\n\t\toptional\n\t\t\tA {{Price 1}}\nconstraints\n\t{terms} > 3\n"
        f"\t{alternatives}\n"
    )
    target = tmp_path / "out.uvl"
    assert convert(source, target).exit_code == 0
    assert target.read_text().splitlines()[-2:] == [f"\t{terms} > 3", f"\t{alternatives}"]
    again = read_uvl_plain(target)  # the very lines of the input: the same model
    assert isinstance(again, TypedFeatureModel) and len(again.equations) == 2


PIZZAS = CORPUS / "composition" / "Pizzas-imports"


def test_a_composed_model_keeps_its_submodels_beside_the_output(tmp_path: Path) -> None:
    result = convert(PIZZAS / "Pizzas.uvl", tmp_path / "Shop.uvl")
    assert result.exit_code == 0, result.output
    written = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*.uvl"))
    assert written == ["Dough.uvl", "Shop.uvl", "Topping.uvl", "submodels/Size.uvl"]
    assert "imports\n\tTopping as top\n\tsubmodels.Size as Size\n\tDough\n" in (
        (tmp_path / "Shop.uvl").read_text()
    )
    original, again = read_uvl_plain(PIZZAS / "Pizzas.uvl"), read_uvl_plain(tmp_path / "Shop.uvl")
    assert shape(again) == shape(original)
    assert answers(again)["core"] == ["Dough.Dough", "Pizza", "Size.Size", "top.Topping"]


def test_what_the_importing_file_writes_on_an_imported_root_stays_in_it(tmp_path: Path) -> None:
    (tmp_path / "sub.uvl").write_text(
        "features\n\tS\n\t\toptional\n\t\t\tN {Price 1}\nconstraints\n\tN.Price < 3\n"
    )
    (tmp_path / "main.uvl").write_text(
        "imports\n\tsub as s\nfeatures\n\tR\n\t\toptional\n"
        "\t\t\tInteger s.S cardinality [1..2] {Price 4}\n\t\t\t\tmandatory\n\t\t\t\t\tExtra\n"
        "constraints\n\ts.S > 1 & sum(Price) > 3\n"
    )
    (tmp_path / "out").mkdir()
    result = convert(tmp_path / "main.uvl", tmp_path / "out" / "main.uvl")
    assert result.exit_code == 0, result.output
    assert (
        "\t\t\tInteger s.S cardinality [1..2] {Price 4}\n\t\t\t\tmandatory\n\t\t\t\t\tExtra\n"
        in ((tmp_path / "out" / "main.uvl").read_text())
    )
    assert "N {Price 1}" in (tmp_path / "out" / "sub.uvl").read_text()
    original = read_uvl_plain(tmp_path / "main.uvl")
    again = read_uvl_plain(tmp_path / "out" / "main.uvl")
    assert shape(again) == shape(original)
    assert answers(again) == answers(original)


def test_a_conversion_beside_its_input_leaves_the_submodels_and_replaces_no_input(
    tmp_path: Path,
) -> None:
    folder = tmp_path / "shop"
    folder.mkdir()
    for path in PIZZAS.rglob("*.uvl"):
        copy = folder / path.relative_to(PIZZAS)
        copy.parent.mkdir(exist_ok=True)
        copy.write_bytes(path.read_bytes())
    before = {p: p.read_bytes() for p in folder.rglob("*.uvl")}
    result = convert(folder / "Pizzas.uvl", folder / "Again.uvl")
    assert result.exit_code == 0, result.output
    assert "submodel" not in result.output
    assert {p: p.read_bytes() for p in folder.rglob("*.uvl") if p.name != "Again.uvl"} == before
    # a submodel's output path is another input: refused, nothing written
    (folder / "sub").mkdir()
    (folder / "sub" / "Dough.uvl").write_bytes((folder / "Dough.uvl").read_bytes())
    (folder / "Two.uvl").write_text(
        "imports\n\tDough\n\tsub.Dough as other\nfeatures\n\tR\n\t\tmandatory\n"
        "\t\t\tDough.Dough\n\t\t\tother.Dough\n"
    )
    result = convert(folder / "Two.uvl", folder / "sub" / "Two.uvl")
    assert result.exit_code == 2
    assert f"writing {folder / 'sub' / 'Dough.uvl'} would replace an input" in result.output
    assert not (folder / "sub" / "Two.uvl").exists()


SUB = "features\n\tS\n\t\toptional\n\t\t\tInteger N\nconstraints\n\tN < 3\n"


@pytest.mark.parametrize("suffix", [".fm", ".xml"])
@pytest.mark.parametrize(
    ("text", "where", "part"),
    [
        (
            "features\n\tR\n\t\toptional\n\t\t\tA\n\t\t\tString Name\n\t\t\tB cardinality [1..2]\n",
            "5:11",
            "typed feature Name (String)",
        ),
        (
            "features\n\tR\n\t\toptional\n\t\t\tB cardinality [1..2]\n\t\t\tString Name\n",
            "4:18",
            "feature cardinality of B",
        ),
        (
            'features\n\tR\n\t\toptional\n\t\t\t"A b" {Price 2}\n'
            'constraints\n\tR => "A b"\n\t"A b".Price * 3 > 5\n',
            "7:2",
            'constraint "A b".Price * 3 > 5',
        ),
        (  # a constraint in an attribute stands before the typed feature after it
            "features\n\tR {constraint A.Price > 1}\n\t\toptional\n\t\t\tA {Price 2}\n"
            "\t\t\tReal X\n",
            "2:16",
            "constraint A.Price > 1",
        ),
        (  # an imported model's parts stand where it is placed, located in its file
            "imports\n\tsub\nfeatures\n\tR\n\t\toptional\n\t\t\tsub.S\n\t\t\tInteger M\n",
            "sub.uvl:4:12",
            "typed feature sub.N (Integer)",
        ),
    ],
)
def test_fm_and_featureide_refuse_the_first_typed_part_located(
    tmp_path: Path, suffix: str, text: str, where: str, part: str
) -> None:
    (tmp_path / "sub.uvl").write_text(SUB)
    source = tmp_path / "typed.uvl"
    source.write_text(text)
    target = tmp_path / f"out{suffix}"
    result = convert(source, target)
    assert result.exit_code == 1, result.output
    located = str(tmp_path / where) if where.startswith("sub") else f"{source}:{where}"
    target_name = {".fm": "FeatureModel (.fm)", ".xml": "FeatureIDE XML"}[suffix]
    assert result.output.startswith(
        f"{located}: error: {part}: spl convert to {target_name} cannot carry it"
    ), result.output
    assert "Traceback" not in result.output
    assert not target.exists()


def test_a_boolean_model_still_converts_to_every_format(tmp_path: Path) -> None:
    source = CORPUS / "boolean_level" / "attributes.uvl"
    for suffix in (".fm", ".xml", ".uvl"):
        assert convert(source, tmp_path / f"out{suffix}").exit_code == 0


def test_the_help_says_what_each_target_keeps() -> None:
    shown = " ".join(CliRunner().invoke(main, ["convert", "--help"]).output.split())
    assert "UVL every language level" in shown
    assert "FeatureIDE XML the Boolean level" in shown


def test_a_refused_part_is_a_model_error_for_callers_too(tmp_path: Path) -> None:
    source = tmp_path / "typed.uvl"
    source.write_text("features\n\tR\n\t\toptional\n\t\t\tInteger N\n")
    with pytest.raises(ModelError) as refused:
        converted_files(source, tmp_path / "out.fm")
    assert str(refused.value.diagnostics[0]).startswith(f"{source}:4:12: error: typed feature N")


def test_an_average_uvl_cannot_say_again_is_refused_located(tmp_path: Path) -> None:
    # avg over an attribute kept as written, of typed features: no UVL text counts the
    # selected ones (a typed feature's name is its value), so the conversion says so
    source = tmp_path / "avg.uvl"
    source.write_text(
        'features\n\tR\n\t\toptional\n\t\t\tInteger A {"My Price" 2}\n\t\t\tB {"My Price" 3}\n'
        'constraints\n\tA < 5\n\tavg("My Price") > 2\n'
    )
    result = convert(source, tmp_path / "out.uvl")
    assert result.exit_code == 1
    assert result.output == (
        f'{source}:8:2: error: avg("My Price") over typed features cannot be written as UVL '
        "that reads back\n"
    )
    assert not (tmp_path / "out.uvl").exists()


def test_a_file_stem_uvl_cannot_quote_becomes_an_identifier_namespace(tmp_path: Path) -> None:
    source = tmp_path / 'odd"stem..uvl'
    source.write_text("features\n\tR\n\t\toptional\n\t\t\tInteger N\n")
    assert convert(source, tmp_path / "out.uvl").exit_code == 0
    assert (tmp_path / "out.uvl").read_text().startswith("namespace odd_stem_\n")
    assert read_uvl_plain(tmp_path / "out.uvl").written_name == "odd_stem_"


def test_an_import_the_tree_never_places_is_left_out(tmp_path: Path) -> None:
    (tmp_path / "main.uvl").write_text(
        "imports\n\tDough\n\tTopping\nfeatures\n\tR\n\t\tmandatory\n\t\t\tDough.Dough\n"
    )
    for name in ("Dough", "Topping"):
        (tmp_path / f"{name}.uvl").write_bytes((PIZZAS / f"{name}.uvl").read_bytes())
    (tmp_path / "out").mkdir()
    result = convert(tmp_path / "main.uvl", tmp_path / "out" / "main.uvl")
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["Dough.uvl", "main.uvl"]
    assert "imports\n\tDough\n\nfeatures\n" in (tmp_path / "out" / "main.uvl").read_text()
    original = read_uvl_plain(tmp_path / "main.uvl")
    assert shape(read_uvl_plain(tmp_path / "out" / "main.uvl")) == shape(original)
