"""Selection checking: invalid (with minimal, located explanations), complete, incomplete."""

from __future__ import annotations

import pytest

from spl.core.diagnostics import Location, ModelError
from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.resolution.selection import check_selection

from support.analysis_models import binary, constraint, mapping3d, ref


@pytest.fixture
def mapping():
    m, fs = mapping3d()
    # line 18 of mapping.fm, as in the example of docs/fm.md
    m.constraints.append(
        constraint(binary("excludes", ref("Roomba", fs), ref("AdditionalPC", fs)), 18)
    )
    with FeatureModelFormula(m) as formula:
        yield formula


def test_complete_selection_is_completed_by_propagation(mapping) -> None:
    result = check_selection(mapping, ["YouBot", "Stereo", "Room"])
    assert result.status == "complete" and result.valid and result.complete
    # tree order; AdditionalPC is forced by "Stereo requires AdditionalPC or Depth"
    assert result.features == (
        "Mapping",
        "MobileBase",
        "YouBot",
        "PerceptionSensor",
        "Stereo",
        "Environment",
        "Room",
        "AdditionalPC",
    )
    assert result.added == (
        "Mapping",
        "MobileBase",
        "PerceptionSensor",
        "Environment",
        "AdditionalPC",
    )
    assert "Depth" in result.excluded and "Roomba" in result.excluded
    assert [d.severity for d in result.diagnostics] == ["info"]
    assert "AdditionalPC" in result.diagnostics[0].message
    result.raise_unless_complete()


def test_optional_features_not_selected_are_left_out(mapping) -> None:
    result = check_selection(mapping, ["YouBot", "Depth", "Corridor"])
    assert result.status == "complete"
    assert "AdditionalPC" not in result.features and "Logging" not in result.features


def test_incomplete_selection_lists_the_open_choices(mapping) -> None:
    result = check_selection(mapping, ["Roomba"])
    assert result.status == "incomplete" and result.valid and not result.complete
    # Roomba excludes Stereo, so Depth is forced; the environment stays open
    assert "Depth" in result.added
    assert [(c.rule.text, c.candidates) for c in result.open_choices] == [
        ("Environment: exactly one of Room, Corridor", ("Room", "Corridor"))
    ]
    assert str(result.open_choices[0]) == (
        "Environment: exactly one of Room, Corridor (mapping.fm:7:5): choose among Room, Corridor"
    )
    errors = [d for d in result.diagnostics if d.severity == "error"]
    assert [str(d.location) for d in errors] == ["mapping.fm:7:5"]
    with pytest.raises(ModelError):
        result.raise_unless_complete()


def test_open_choice_from_a_constraint(mapping) -> None:
    result = check_selection(mapping, ["YouBot", "Room"], deselected=["Depth"])
    # Stereo is forced, so AdditionalPC is too: complete
    assert result.status == "complete" and "AdditionalPC" in result.added
    result = check_selection(mapping, ["YouBot", "Room", "Stereo"])
    assert result.status == "complete"


def test_invalid_selection_names_the_violated_rule_with_its_location(mapping) -> None:
    where = {
        "Roomba": Location("product.yaml", 3, 5),
        "AdditionalPC": Location("product.yaml", 4, 5),
    }
    result = check_selection(mapping, ["Roomba", "AdditionalPC", "Depth", "Room"], locations=where)
    assert result.status == "invalid" and not result.valid
    assert result.explanation() == "Roomba excludes AdditionalPC (mapping.fm:18:5)"
    assert result.conflicting == ("Roomba", "AdditionalPC")  # Depth, Room are not part of it
    (diagnostic,) = result.diagnostics
    assert str(diagnostic) == (
        "product.yaml:3:5: error: invalid selection: selecting Roomba, AdditionalPC contradicts: "
        "Roomba excludes AdditionalPC (mapping.fm:18:5)"
    )


def test_two_members_of_an_alternative(mapping) -> None:
    result = check_selection(mapping, ["YouBot", "Roomba"])
    assert result.explanation() == "MobileBase: exactly one of YouBot, Roomba (mapping.fm:4:5)"


def test_explanation_is_a_minimal_chain_of_rules(mapping) -> None:
    # Roomba excludes Stereo; deselecting Depth forces Stereo (exactly one sensor)
    result = check_selection(mapping, ["Roomba"], deselected=["Depth"])
    assert result.status == "invalid"
    assert [r.text for r in result.conflict] == [
        "MobileBase needs its parent Mapping",
        "PerceptionSensor is mandatory in Mapping",
        "Roomba needs its parent MobileBase",
        "PerceptionSensor: exactly one of Stereo, Depth",
        "Roomba excludes Stereo",
    ]
    assert result.conflicting == ("Roomba", "Depth")
    assert "deselecting Depth" in result.diagnostics[0].message


def test_unknown_and_contradictory_names_are_located_errors(mapping) -> None:
    where = {"Rooomba": Location("p.yaml", 2, 3), "YouBot": Location("p.yaml", 3, 3)}
    with pytest.raises(ModelError) as caught:
        check_selection(mapping, ["Rooomba", "YouBot"], deselected=["YouBot"], locations=where)
    messages = [str(d) for d in caught.value.diagnostics]
    assert messages == [
        "p.yaml:2:3: error: unknown feature 'Rooomba' (did you mean Roomba?)",
        "p.yaml:3:3: error: feature YouBot is both selected and deselected",
    ]


def test_every_unknown_name_is_reported_and_the_first_ones_get_a_suggestion(mapping) -> None:
    from spl.resolver.resolution.selection import SUGGESTED

    names = [f"Rooomba{i}" for i in range(SUGGESTED + 5)]
    with pytest.raises(ModelError) as caught:
        check_selection(mapping, ["YouBot", *names])
    messages = [d.message for d in caught.value.diagnostics]
    assert len(messages) == SUGGESTED + 5
    assert messages[0] == "unknown feature 'Rooomba0' (did you mean Roomba?)"
    assert all("did you mean Roomba?" in m for m in messages[:SUGGESTED])
    assert messages[SUGGESTED:] == [f"unknown feature {n!r}" for n in names[SUGGESTED:]]


def test_any_selection_of_a_void_model_names_the_contradiction() -> None:
    from support.analysis_models import all_features, feature, group, model

    m = model(feature("R", group("mandatory", feature("A", line=2)), line=1))
    fs = all_features(m)
    m.constraints.append(constraint(binary("excludes", ref("A", fs), ref("R", fs)), 5))
    result = check_selection(m, [])
    assert result.status == "invalid" and result.conflicting == ()
    assert result.explanation() == (
        "R is the root feature and always selected (mapping.fm:1:5); "
        "A is mandatory in R (mapping.fm:2:5); A excludes R (mapping.fm:5:5)"
    )
    assert "the feature model (it has no product)" in result.diagnostics[0].message
