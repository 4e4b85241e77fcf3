"""A ``constraint`` or ``constraints`` entry inside a nested attribute value (the UVL
grammar's ``attribute`` rule holds both kinds at every depth) is a constraint of the
model, analysed like any other, and left out of the attribute text kept as written
(docs/fm.md, "Attributes kept as written")."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from spl.cli import main
from spl.dsl.interop.interchange import UVL_ATTRIBUTES
from spl.dsl.interop.uvl import read_uvl_plain
from spl.dsl.interop.uvl_typed import TypedFeatureModel

CART = (
    "features\n"
    "\tShop\n"
    "\t\toptional\n"
    "\t\t\tCart {Package {Name 'P', constraint Cart => !Express}, "
    "Tags ['a', {constraints [Express => Cart]}]}\n"
    "\t\t\tExpress {Empty {constraints []}}\n"
    "\t\t\tGift\n"
)


def analyze(path: Path) -> dict:
    result = CliRunner().invoke(main, ["analyze", "--json", "--count", str(path)])
    assert result.exit_code == 0, result.output
    return json.loads(result.output)


def test_a_nested_constraint_makes_a_feature_dead(tmp_path: Path) -> None:
    """``Express => Cart`` (in a vector) and ``Cart => !Express`` (in a nested value):
    no product has Express."""
    path = tmp_path / "cart.uvl"
    path.write_text(CART, encoding="utf-8")
    model = read_uvl_plain(path)
    assert [(c.srcLine, c.srcCol) for c in model.constraints] == [(4, 40), (4, 84)]
    report = analyze(path)
    assert (report["constraints"], report["dead"], report["products"]) == (2, ["Express"], 4)
    checked = CliRunner().invoke(main, ["check", str(path)])
    assert checked.exit_code == 0
    assert checked.stdout == f"{path}: ok: 4 features, 2 constraints\n"
    assert checked.stderr == (
        f"{path}:5:4: warning: feature Express is dead: no product of the model contains it\n"
    )


def test_the_kept_text_holds_the_rest_and_a_written_model_holds_each_constraint_once(
    tmp_path: Path,
) -> None:
    path = tmp_path / "cart.uvl"
    path.write_text(CART, encoding="utf-8")
    kept = {
        feature.name: attribute.value
        for group in read_uvl_plain(path).root.groups
        for feature in group.features
        for attribute in feature.attributes
        if attribute.name == UVL_ATTRIBUTES
    }
    assert kept == {"Cart": "Package {Name 'P'}, Tags ['a', {}]", "Express": "Empty {}"}
    written = tmp_path / "written.uvl"
    assert CliRunner().invoke(main, ["convert", str(path), str(written)]).exit_code == 0
    text = written.read_text(encoding="utf-8")
    assert text.count("Cart => !Express") == 1 and text.count("Express => Cart") == 1
    again = analyze(written)
    first = analyze(path)
    assert {k: again[k] for k in ("constraints", "dead", "core", "products")} == {
        k: first[k] for k in ("constraints", "dead", "core", "products")
    }


def test_a_nested_equation_is_read_on_the_typed_level(tmp_path: Path) -> None:
    path = tmp_path / "sized.uvl"
    path.write_text(
        "features\n\tShop\n\t\toptional\n"
        "\t\t\tInteger Size {Bounds {Unit 'cm', constraint Size => Size > 5 & Size < 3}}\n"
        "\t\t\tGift\n",
        encoding="utf-8",
    )
    model = read_uvl_plain(path)
    assert isinstance(model, TypedFeatureModel) and len(model.equations) == 1
    assert (model.equations[0].srcLine, model.equations[0].srcCol) == (4, 48)
    assert analyze(path)["dead"] == ["Size"]


def test_a_fault_in_a_nested_constraint_is_located(tmp_path: Path) -> None:
    path = tmp_path / "bad.uvl"
    path.write_text(
        "features\n\tShop\n\t\toptional\n\t\t\tA {P {constraint A => Nope}}\n"
        "\t\t\tB {Q [{constraints [A, ]}]}\n",
        encoding="utf-8",
    )
    result = CliRunner().invoke(main, ["check", str(path)])
    assert result.exit_code == 1 and "Traceback" not in result.output
    assert result.output.splitlines() == [
        f"{path}:4:26: error: unknown feature Nope",
        f"{path}:5:27: error: expected a feature, ! or (, got ]",
    ]
