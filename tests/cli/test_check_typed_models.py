"""``spl check FILE`` of a feature model says what the model holds, typed parts too, and
checks it as ``spl analyze`` analyses it: a void model is an error at its root, a dead
feature a warning at its declaration, on every language level (docs/commands.md, "spl
check"; docs/fm.md)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from spl.cli import main
from spl.dsl.interop.interchange import written_names
from spl.dsl.interop.uvl import read_uvl_plain
from spl.dsl.interop.uvl_typed import TypedFeatureModel, features_of

from support.fm_typed_semantics import brute_force

CORPUS = Path(__file__).parents[1] / "data" / "uvl-parser" / "test_models"
TYPED = sorted(
    path
    for path in CORPUS.rglob("*.uvl")
    if "faulty" not in path.parts and path.name != "dotinfeaturename.uvl"
    if isinstance(read_uvl_plain(path), TypedFeatureModel)
)
DEAD = re.compile(r"feature (.+) is dead: no product of the model contains it")


def check(*args: object):
    return CliRunner().invoke(main, ["check", *map(str, args)])


def test_the_summary_of_a_typed_model_says_what_it_holds() -> None:
    expected = {
        "complex/bike.uvl": "11 features (1 Integer, 1 String), 1 feature cardinality, "
        "6 constraints (1 Boolean, 2 aggregate, 1 string, 2 comparison)",
        "type_level/string-constraints.uvl": "3 features (2 String), "
        "5 constraints (1 Boolean, 4 string)",
        "arithmetic_level/expressions.uvl": "3 features, 24 constraints (0 Boolean, 24 arithmetic)",
        "arithmetic_level/feature_cardinality/fm18_fc.uvl": "7 features, "
        "2 feature cardinalities, 2 constraints (2 Boolean)",
        "arithmetic_level/feature_cardinality/fm01_fc.uvl": "2 features, "
        "1 feature cardinality, 0 constraints",
    }
    for name, summary in expected.items():
        result = check(CORPUS / name)
        assert result.exit_code == 0, result.output
        assert result.output == f"{CORPUS / name}: ok: {summary}\n"
    boolean = check(CORPUS / "boolean_level" / "cardinality.uvl")
    assert boolean.output.endswith(": ok: 4 features, 0 constraints\n"), boolean.output


@pytest.mark.parametrize("path", TYPED, ids=[str(p.relative_to(CORPUS)) for p in TYPED])
def test_void_and_dead_are_what_brute_force_finds(path: Path) -> None:
    """Every vendored typed model brute force can enumerate (no typed feature: its
    products are those of the tree whose equations hold)."""
    model = read_uvl_plain(path)
    assert isinstance(model, TypedFeatureModel)
    result = check(path, "--json")
    report = json.loads(result.output)
    written = written_names(model)
    features = {written[f.name]: f for f in features_of(model)}
    if model.types:  # unbounded values: whatever z3 finds is located and consistent
        assert all(d["line"] >= 1 and d["file"] == str(path) for d in report["diagnostics"])
        return
    valid = brute_force(model)
    if not valid:
        assert result.exit_code == 1
        assert report["errors"] == 1 and report["files"][0]["ok"] is False
        [void] = report["diagnostics"]
        assert "has no product" in void["message"]
        assert (void["line"], void["col"]) == (model.root.srcLine, model.root.srcCol)
        return
    assert result.exit_code == 0 and report["errors"] == 0
    dead = set(features) - {written[name] for product in valid for name in product}
    found = {DEAD.fullmatch(d["message"]).group(1): d for d in report["diagnostics"]}
    assert set(found) == dead
    for name, diagnostic in found.items():
        assert diagnostic["severity"] == "warning"
        assert (diagnostic["line"], diagnostic["col"]) == (
            features[name].srcLine,
            features[name].srcCol,
        )


def test_a_dead_typed_feature_is_a_located_warning(tmp_path: Path) -> None:
    """``Size`` may be chosen only with a value above 5 and below 3: no product has it;
    the model keeps its other products (Size deselected is 0, docs/fm.md)."""
    path = tmp_path / "sized.uvl"
    path.write_text(
        "features\n"
        "\tShop\n"
        "\t\toptional\n"
        "\t\t\tInteger Size\n"
        "\t\t\tReal Discount\n"
        "constraints\n"
        "\tSize => Size > 5 & Size < 3\n"
        "\tDiscount < 0.5\n",
        encoding="utf-8",
    )
    result = CliRunner().invoke(main, ["check", str(path)])
    assert result.exit_code == 0, result.output
    assert result.stdout == (
        f"{path}: ok: 3 features (1 Integer, 1 Real), 2 constraints (0 Boolean, 2 comparison)\n"
    )
    assert result.stderr == (
        f"{path}:4:12: warning: feature Size is dead: no product of the model contains it\n"
    )
    report = json.loads(check(path, "--json").output)
    assert (report["errors"], report["warnings"]) == (0, 1)
    analyzed = json.loads(CliRunner().invoke(main, ["analyze", "--json", str(path)]).output)
    assert analyzed["dead"] == ["Size"] and analyzed["satisfiable"]


def test_a_void_typed_model_is_an_error_at_its_root() -> None:
    """``F.Price - C.Price == 7.00`` holds for no choice of F and C (0.5 - 7.5, 0.5, -7.5
    or 0)."""
    path = CORPUS / "arithmetic_level" / "arithmetic_constraints02.uvl"
    result = check(path)
    assert result.exit_code == 1 and "Traceback" not in result.output
    assert result.output == (
        f"{path}:2:5: error: feature model arithmetic_constraints02 has no product: its "
        "tree, groups and constraints contradict each other (the model is void, every "
        "feature dead)\n"
    )


def test_a_boolean_model_gets_the_same_findings_in_every_format(tmp_path: Path) -> None:
    uvl = tmp_path / "shop.uvl"
    uvl.write_text(
        'features\n\tShop\n\t\toptional\n\t\t\tA\n\t\t\t"B 2"\nconstraints\n'
        '\tA => "B 2"\n\tA => !"B 2"\n',
        encoding="utf-8",
    )
    findings = {}
    for suffix in (".uvl", ".fm", ".xml"):
        path = uvl.with_suffix(suffix)
        if suffix != ".uvl":
            assert CliRunner().invoke(main, ["convert", str(uvl), str(path)]).exit_code == 0
        result = check(path)
        assert result.exit_code == 0, result.output
        assert result.stdout == f"{path}: ok: 3 features, 2 constraints\n"
        findings[suffix] = result.stderr.split(": warning: ")[1]
    assert set(findings.values()) == {"feature A is dead: no product of the model contains it\n"}
    assert check(uvl).stderr.startswith(f"{uvl}:4:4: warning:")


def test_a_uvl_model_is_still_checked_whole(tmp_path: Path) -> None:
    """The check reads the plain model spl analyze reads and builds it as every other
    command does, which checks a capability condition (docs/fm.md, "Capabilities")."""
    path = tmp_path / "robot.uvl"
    path.write_text("features\n\tR\n\t\toptional\n\t\t\tA {capability 'base = '}\n")
    result = check(path)
    assert result.exit_code == 1 and "Traceback" not in result.output
    assert result.output.startswith(f"{path}:4:7: error: capability 'base = ': syntax error")
