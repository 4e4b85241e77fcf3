"""Product selection files are user input: every problem is located in the YAML."""

from __future__ import annotations

import pytest

from spl.core.diagnostics import ModelError
from spl.resolver.resolution.product_selection import (
    apply_overrides,
    load_selection_file,
    selection_from_list,
)


def problems(tmp_path, text: str) -> list[str]:
    path = tmp_path / "p.yaml"
    path.write_text(text)
    with pytest.raises(ModelError) as caught:
        load_selection_file(path)
    return [str(d).replace(str(tmp_path) + "/", "") for d in caught.value.diagnostics]


def test_full_selection_is_read(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(
        "product: youbot_stereo_room\n"
        "features: [YouBot, Stereo]\n"
        "sharing: {SharedMap: private}\n"
        "attributes: {Logging.rate: 5.0}\n"
        'deployment: {Robot: {robot_id: youbot_07, url: "wss://rce.example.org:9000/"}}\n'
    )
    selection = load_selection_file(path)
    assert selection.name == "youbot_stereo_room"
    assert selection.features == ["YouBot", "Stereo"]
    assert selection.sharing == {"SharedMap": "private"}
    assert selection.attributes == {"Logging.rate": 5.0}
    assert selection.deployment == {
        "Robot": {"robot_id": "youbot_07", "url": "wss://rce.example.org:9000/"}
    }
    assert str(selection.location("Stereo")).endswith("p.yaml:2:20")


def test_errors_are_located(tmp_path):
    assert problems(
        tmp_path,
        "product: p\n"
        "features: [YouBot, 'Bad Name']\n"
        "colour: red\n"
        "sharing: {SharedMap: everyone}\n"
        "deployment: {Robot: {robot_id: '$(reboot)', password: x}}\n",
    ) == [
        "p.yaml:2:20: error: features: 'Bad Name' is not a feature name",
        "p.yaml:3:1: error: unknown key 'colour' (expected product, features, deselected, "
        "sharing, attributes, deployment, capabilities)",
        "p.yaml:4:22: error: sharing: expected one of private, protected, public",
        "p.yaml:5:32: error: deployment: robot_id '$(reboot)' is not valid",
        "p.yaml:5:45: error: deployment: unknown setting 'password' (robot_id, url)",
    ]


def test_invalid_yaml_and_empty_selection(tmp_path):
    (invalid,) = problems(tmp_path, "features: [YouBot\n")
    assert invalid.startswith("p.yaml:2:1: error: invalid YAML")
    assert problems(tmp_path, "product: p\n") == [
        "p.yaml:1:1: error: no features selected (key 'features' or 'capabilities')"
    ]


def test_command_line_forms_and_overrides():
    selection = selection_from_list("YouBot, Stereo,Room")
    assert selection.features == ["YouBot", "Stereo", "Room"]
    twice = selection_from_list("YouBot,Stereo,YouBot")  # was named YouBot_Stereo_YouBot
    assert (twice.name, twice.features) == ("YouBot_Stereo", ["YouBot", "Stereo"])
    apply_overrides(selection, ["SharedMap=public"], ["Logging.rate=2", "Mode.name=fast"])
    assert selection.sharing == {"SharedMap": "public"}
    # text until the product is resolved: the attribute's type says how to read it
    assert selection.attributes == {"Logging.rate": "2", "Mode.name": "fast"}
    with pytest.raises(ModelError) as caught:
        apply_overrides(selection, ["SharedMap=everyone"], ["rate=2"])
    assert [str(d) for d in caught.value.diagnostics] == [
        "--set:1:1: error: 'rate=2': expected FEATURE.ATTRIBUTE=VALUE",
        "--sharing:1:1: error: 'SharedMap=everyone': expected FEATURE=private|protected|public",
    ]
    with pytest.raises(ModelError):
        selection_from_list("YouBot,<script>")


def test_a_key_given_twice_is_refused(tmp_path):
    # was: features of both lines merged, a repeated product or attribute kept the last
    assert problems(
        tmp_path, "product: dup\nfeatures: [Log]\nfeatures: [Move]\nattributes: {A.b: 1, A.b: 2}\n"
    ) == [
        "p.yaml:3:1: error: duplicate key 'features' (first at line 2)",
        "p.yaml:4:22: error: duplicate key 'A.b' (first at line 4)",
    ]


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("x: &a {y: *a}\n", "1:4"),
        ("features: [A]\nsharing: &a {SharedMap: *a}\n", "2:10"),
        ("&a {features: [A], again: *a}\n", "1:1"),
        ("features: &l [A, *l]\n", "1:11"),
    ],
)
def test_a_recursive_alias_is_refused_not_walked_forever(tmp_path, text, where):
    # was: spl resolve, explain, check and validate never ended (found by fuzzing)
    assert problems(tmp_path, text) == [
        f"p.yaml:{where}: error: invalid YAML: a recursive alias (a node that holds itself)"
    ]


def test_an_alias_used_twice_is_no_recursion(tmp_path):
    selection = tmp_path / "p.yaml"
    selection.write_text("product: p\nfeatures: &f [A, B]\ndeselected: [C]\n")
    assert load_selection_file(selection).features == ["A", "B"]
    shared = tmp_path / "q.yaml"
    shared.write_text("product: q\nattributes: {F.a: &v 1, G.b: *v}\nfeatures: [F, G]\n")
    assert load_selection_file(shared).attributes == {"F.a": 1, "G.b": 1}
