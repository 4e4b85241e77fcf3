"""The builder run over plain objects (``spl.dsl.tsm.language.check_text``, what ``spl check
FILE.tsm`` and the editor run) finds exactly what it finds run over pyecore's own
classes: the same diagnostics, in the same order, and for a text without errors the
same summary, printed model and places. ``parse_text`` builds over plain objects and
copies the result into pyecore (``spl.core.emf.copy_model``): its model equals the one
built through pyecore, feature by feature (``spl.core.emf_compare.differences``). Checked on every
shipped and test model, the mutation corpus of tests/dsl/test_tsm_reader.py and
generated, mutated lines.
"""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given, settings, strategies as st
from test_tsm_reader import SHIPPED, SUBSTITUTES

from spl.core.diagnostics import ModelError
from spl.core.emf_compare import differences
from spl.dsl.tsm import language as tsm, plain as tsm_plain
from spl.dsl.tsm.printer import print_model
from spl.dsl.workspace import Workspace
from spl.metamodels import tsm as ecore_metamodel

from support import textx_trees
from support.hypothesis_budget import examples
from support.model_mutations import mutate, mutations
from support.random_lines import line_specs, tsm_text
from support.textx_trees import ROOT


def outcome(build: Any, text: str) -> tuple[str, ...]:
    """What a build says of ``text``: its diagnostics, or its summary, printed model and
    the class, name and location of every element."""
    try:
        system = build(text, "m.tsm")
    except ModelError as exc:
        return tuple(f"{d} [{d.severity} {d.code}]" for d in exc.diagnostics)
    return tsm.summary(system), print_model(system), *places(system)


def places(element: Any) -> list[str]:
    """Every element under ``element`` (containment, in feature order) and its place."""
    found = [
        f"{element.eClass.name} {getattr(element, 'name', '')} "
        f"{element.srcFile}:{element.srcLine}:{element.srcCol}"
    ]
    for feature in element.eClass.eAllStructuralFeatures():
        if getattr(feature, "containment", False):
            value = getattr(element, feature.name)
            for child in value if feature.many else [value] if value is not None else []:
                found += places(child)
    return found


def through_pyecore(text: str, filename: str) -> Any:
    """The builder run over pyecore's classes, every feature set through pyecore."""
    return tsm._parse(text, filename, ecore_metamodel())


def assert_same(text: str) -> None:
    built = outcome(through_pyecore, text)  # each build itself: no workspace remembers
    assert outcome(tsm.check_text, text) == built
    assert outcome(tsm.parse_text, text) == built
    try:
        model = tsm.parse_text(text, "m.tsm")
    except ModelError:
        return  # refused, with the diagnostics compared above
    assert list(differences(through_pyecore(text, "m.tsm"), model)) == []


def mutated_texts(count: int, seed: int) -> list[str]:
    """Lines deleted and doubled, tokens deleted or replaced: a fixed random sample."""
    return textx_trees.mutated_texts(SHIPPED, SUBSTITUTES, count, seed)


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_shipped_model_checks_alike_in_plain_objects(path) -> None:
    assert_same(path.read_text(encoding="utf-8"))


def test_mutated_shipped_models_check_alike_in_plain_objects() -> None:
    for text in mutated_texts(600, 17):
        assert_same(text)


@settings(max_examples=examples(30), deadline=None)
@given(line_specs(), st.data())
def test_generated_and_mutated_lines_check_alike_in_plain_objects(spec, data) -> None:
    text = tsm_text(spec)
    assert_same(text)
    assert_same(mutate(text, data.draw(mutations(text))))


def test_plain_elements_answer_like_the_metamodels_objects() -> None:
    """Defaults, containment, eContainer, eClass and enum literals as pyecore has them."""
    T, E = tsm_plain.metamodel(), ecore_metamodel()
    node, ecore_node = T.Node(name="n"), E.Node(name="n")
    for feature in ("name", "optional", "sharing", "package", "args", "srcLine"):
        assert getattr(node, feature) == getattr(ecore_node, feature), feature
    assert node.eClass is E.Node.eClass and node.sharing is E.SharingMode.private
    container = T.CloudContainer(name="c")
    container.nodes.append(node)
    container.endpoint = T.Endpoint()
    assert node.eContainer() is container and container.endpoint.eContainer() is container
    call = T.CallExpression(function="max", arguments=[T.NumberLiteral(value="1")])
    assert call.arguments[0].eContainer() is call
    container.eSet("cpu", 2)
    assert container.eGet("cpu") == 2 and container.size is None
    assert T.SharingMode is E.SharingMode


def test_a_text_the_plain_build_refused_is_refused_again_without_building(monkeypatch) -> None:
    """The editor's folder check meets a refused .tsm up to three times (the line, the
    .rm's models, the file alone): only the plain build reads it. The refusal is the
    workspace's: without one, or in another, the text is built again."""
    text = SHIPPED[0].read_text(encoding="utf-8") + "\nbridge Robot.Nothing -> Nowhere.Nothing\n"
    workspace = Workspace()
    with pytest.raises(ModelError) as plain:
        tsm.check_text(text, "m.tsm", workspace=workspace)
    built: list[str] = []
    real = tsm._parse
    monkeypatch.setattr(tsm, "_parse", lambda *args, **kw: built.append(args[1]) or real(*args))
    with pytest.raises(ModelError) as again:
        tsm.parse_text(text, "m.tsm", workspace)
    with pytest.raises(ModelError) as checked_again:
        tsm.check_text(text, "m.tsm", workspace=workspace)
    assert built == [] and again.value.diagnostics == plain.value.diagnostics
    assert checked_again.value.diagnostics == plain.value.diagnostics
    # another text, or another file, is built; so is the text outside the workspace
    with pytest.raises(ModelError):
        tsm.parse_text(text + " ", "m.tsm", workspace)
    with pytest.raises(ModelError):
        tsm.parse_text(text, "other.tsm", workspace)
    with pytest.raises(ModelError):
        tsm.parse_text(text, "m.tsm")
    with pytest.raises(ModelError):
        tsm.parse_text(text, "m.tsm", Workspace())
    assert built == ["m.tsm", "other.tsm", "m.tsm", "m.tsm"]
    # once the file's text builds, its old refusal is forgotten
    tsm.check_text(SHIPPED[0].read_text(encoding="utf-8"), "m.tsm", workspace=workspace)
    built.clear()
    with pytest.raises(ModelError):
        tsm.parse_text(text, "m.tsm", workspace)
    assert built == ["m.tsm"]
