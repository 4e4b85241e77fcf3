"""Every test model of the UVL project's reference parser (tests/data/uvl-parser): the
valid ones of every language level are read and analysed (the Boolean level on SAT, the
Arithmetic and Type levels on z3), the faulty ones refused for their own fault; always
located, never a traceback."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.interop.interchange import written_names
from spl.dsl.interop.uvl import read_uvl, read_uvl_plain, write_uvl
from spl.dsl.interop.uvl_reader import parse_uvl_plain
from spl.dsl.interop.uvl_typed import TypedFeatureModel
from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.analysis.smt import SmtFormula

from support.fm_semantics import products
from support.fm_typed_semantics import analysis, expected_analysis

CORPUS = Path(__file__).parents[1] / "data" / "uvl-parser" / "test_models"
MODELS = sorted(CORPUS.rglob("*.uvl"))
# the fault each faulty model is refused for (dotinfeaturename: the parser's own tests
# call it misplaced, "should be illegal": a quoted name holds no '.')
FAULTS = {
    "faulty/illegalname.uvl": "expected a feature name, got 12",
    "faulty/missingreference.uvl": "unknown feature C",
    "faulty/same_feature_names.uvl": "duplicate feature Lightsaber",
    "faulty/wrong_attribute_name.uvl": "imported model nested.string-attributes-external not found",
    "faulty/wrongindent.uvl": "expected one root feature",
    "lexing/dotinfeaturename.uvl": "a quoted name is closed on its line and holds no '.'",
}
# what z3 answers for typed models brute force cannot enumerate (unbounded values):
# (satisfiable, core, number of products); the counts checked by the brute force of
# support/fm_typed_semantics.py given the values the constraints leave (Size 30, City
# 'Omashu'; Inch 0, 20, 22 or 25)
TYPED = {
    "type_level/string-constraints.uvl": (True, ["A", "C", "D"], 1),
    "complex/bike.uvl": (True, ["Bike", "Brake", "Inch", "Manufacturer"], 22),
    # City == Pizza.City: the String feature City takes the root's attribute 'Omashu'
    "complex/Sundermann2024_Pizza.uvl": (
        True,
        ["Base", "City", "DeliveryAddress", "Pizza", "Sauce", "Size", "Street"],
        82,
    ),
    # clients == 20 and ceil(clients) < 10 contradict each other
    "complex/Horcas2025_Icecream.uvl": (False, [], 0),
}


def verdict(path: Path) -> tuple[str, list[str]]:
    """("read", []) or ("faulty" | "unsupported", the messages), every message located in
    the corpus."""
    try:
        read_uvl_plain(path)
    except ModelError as exc:
        shown = [str(d) for d in exc.diagnostics]
        assert all(line.startswith(str(CORPUS)) for line in shown), shown
        messages = [d.message for d in exc.diagnostics]
        unsupported = all("not supported" in m for m in messages)
        return ("unsupported" if unsupported else "faulty"), messages
    return "read", []


def test_the_counts() -> None:
    verdicts = [verdict(path)[0] for path in MODELS]
    assert len(MODELS) == 88
    assert (verdicts.count("read"), verdicts.count("unsupported"), verdicts.count("faulty")) == (
        82,
        0,
        6,
    )


@pytest.mark.parametrize("path", MODELS, ids=[str(p.relative_to(CORPUS)) for p in MODELS])
def test_each_model(path: Path) -> None:
    name = str(path.relative_to(CORPUS))
    kind, messages = verdict(path)
    if name in FAULTS:
        assert kind == "faulty" and any(FAULTS[name] in m for m in messages), messages
        return
    assert kind == "read", messages
    typed = read_uvl_plain(path)
    if isinstance(typed, TypedFeatureModel):
        with SmtFormula(typed) as formula:
            found = analysis(formula)
            if name in TYPED:
                shown = (found["satisfiable"], found["core"], found["count"])
                assert shown == TYPED[name], found
            elif not typed.types and not _free_attributes(typed):  # finite: brute force
                assert found == expected_analysis(typed, formula)
            else:
                assert not set(found["core"]) & set(found["dead"]) or not found["satisfiable"]
        return
    model = read_uvl(path)  # and the same model as pyecore objects
    expected = products(model)  # brute force: the models are small
    with FeatureModelFormula(read_uvl_plain(path)) as formula:
        assert formula.satisfiable() == bool(expected)
        everything = frozenset().union(*expected) if expected else frozenset()
        core = frozenset.intersection(*expected) if expected else frozenset()
        assert set(formula.core_features()) == set(core)
        names = set(formula.cnf.names)
        assert set(formula.dead_features()) == (names - everything if expected else names)
        assert formula.count(None).value == len(expected)
    if not any("." in name for name in written_names(model).values()):
        again = parse_uvl_plain(write_uvl(model), str(path))  # written back, read again
        assert sorted(written_names(again).values()) == sorted(written_names(model).values())


def _free_attributes(model: TypedFeatureModel) -> bool:
    """Whether an equation names an attribute declared without a value (a variable)."""
    return any(
        "'attr'" in repr(e.formula) and ", None," in repr(e.formula) for e in model.equations
    )


def test_composition_names_imported_features_as_the_importing_file_does() -> None:
    pizzas = read_uvl_plain(CORPUS / "composition" / "Pizzas-imports" / "Pizzas.uvl")
    with FeatureModelFormula(pizzas) as formula:
        written = written_names(pizzas)
        core = sorted(written[name] for name in formula.core_features())
        assert core == ["Dough.Dough", "Pizza", "Size.Size", "top.Topping"]
        assert formula.count(None).value == 42
    # the imported files' own constraints join the model, located in their files
    nested = read_uvl(CORPUS / "composition" / "nested_main.uvl")
    assert sorted(written_names(nested).values()) == [
        "Root",
        "nesu.F1",
        "nesu.F2",
        "nesu.Root",
        "nesu.nrs.N1",
        "nesu.nrs.N2",
        "nesu.nrs.Nested",
    ]


def test_an_import_cycle_and_a_wrong_placement_are_refused_at_the_import(tmp_path: Path) -> None:
    (tmp_path / "a.uvl").write_text("imports\n\tb\nfeatures\n\tA\n\t\toptional\n\t\t\tb.B\n")
    (tmp_path / "b.uvl").write_text("imports\n\ta\nfeatures\n\tB\n\t\toptional\n\t\t\ta.A\n")
    with pytest.raises(ModelError) as refused:
        read_uvl_plain(tmp_path / "a.uvl")
    assert [str(d) for d in refused.value.diagnostics] == [
        f"{tmp_path / 'b.uvl'}:2:2: error: import cycle: a.uvl -> b.uvl -> a.uvl"
    ]
    (tmp_path / "c.uvl").write_text(
        "imports\n\tb as x\nfeatures\n\tC\n\t\toptional\n\t\t\tx.Nope\n"
    )
    (tmp_path / "b.uvl").write_text("features\n\tB\n\t\toptional\n\t\t\tInner\n")
    with pytest.raises(ModelError) as refused:
        read_uvl_plain(tmp_path / "c.uvl")
    assert [d.message for d in refused.value.diagnostics] == [
        "only the root feature of imported model x (B) can be placed in the tree"
    ]


def test_nested_and_vector_values_are_kept_as_written(tmp_path: Path) -> None:
    path = tmp_path / "values.uvl"
    path.write_text(
        "features\n\tR {size {width 3, height [4, 5]}, \"my key\" 1, plain 2, tags ['a']}\n"
    )
    written = write_uvl(read_uvl(path))
    assert "\tR {size {width 3, height [4, 5]}, \"my key\" 1, tags ['a'], plain 2}" in written
    with pytest.raises(ModelError, match="expected an attribute name"):
        parse_uvl_plain("features\n\tR {size {'w' 3}}\n")
