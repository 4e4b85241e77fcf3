"""Capability-driven selection: a robot capability file chooses features through the
``capability`` conditions of the feature model, and says which capability chose what."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from spl.cli import main
from spl.core.diagnostics import ModelError
from spl.resolver.resolution.capabilities import choose_features, load_capabilities
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import ProductSelection, load_selection_file

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"
YOUBOT = "base: youbot\nsensors: [stereo_camera, bumper]\nonboard_pc: true\n"
ROOMBA = "base: roomba\nsensors: depth_camera\ncompute: {onboard_pc: false}\n"


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def run(*args: str | Path) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, [str(a) for a in args])
    return result.exit_code, result.stdout, result.stderr


@pytest.fixture(scope="module")
def line():
    return load_product_line(MAPPING)


def test_capabilities_select_and_deselect_features(tmp_path, line) -> None:
    capabilities = load_capabilities(write(tmp_path, "youbot.yaml", YOUBOT))
    choices = {(c.feature, c.selected) for c in choose_features(line.fm, capabilities)}
    assert choices == {
        ("YouBot", True),
        ("Roomba", False),
        ("Stereo", True),
        ("Depth", False),
        ("AdditionalPC", True),
    }


def test_nested_capabilities_and_scalars_for_lists(tmp_path) -> None:
    capabilities = load_capabilities(write(tmp_path, "roomba.yaml", ROOMBA))
    assert capabilities.values == {
        "base": "roomba",
        "sensors": "depth_camera",
        "compute.onboard_pc": False,
    }
    assert str(capabilities.locations["compute.onboard_pc"]).endswith("roomba.yaml:3:11")


def test_undeclared_capabilities_leave_the_choice_open(tmp_path, line) -> None:
    capabilities = load_capabilities(write(tmp_path, "roomba.yaml", ROOMBA))
    chosen = {c.feature: c.selected for c in choose_features(line.fm, capabilities)}
    # `onboard_pc` is not declared (compute.onboard_pc is another capability)
    assert chosen == {"YouBot": False, "Roomba": True, "Stereo": False, "Depth": True}
    selection = ProductSelection("roomba", ["Room"])
    selection.capabilities = capabilities
    resolution = resolve(line, selection)
    assert set(resolution.product.features) >= {"Roomba", "Depth", "Room"}
    assert "AdditionalPC" not in resolution.product.features  # excluded by Roomba


def test_resolve_reports_which_capability_chose_which_feature(tmp_path) -> None:
    robot = write(tmp_path, "youbot_07.yaml", YOUBOT)
    out = tmp_path / "bundle"
    code, stdout, stderr = run(
        "resolve", MAPPING, "--capabilities", robot, "--features", "Room", "-o", out
    )
    assert code == 0, stderr
    assert stdout.splitlines()[0].startswith("product youbot_07: AdditionalPC, ")
    assert (
        f'  capability base: youbot ({robot}:1:1) selects YouBot: base = "youbot" holds '
        f"({MAPPING / 'mapping.fm'}:10:29)"
    ) in stdout.splitlines()
    assert any("deselects Depth" in line for line in stdout.splitlines())
    assert "migrated: MapOptimizer from MappingCloud to Robot" in stdout  # AdditionalPC


def test_capabilities_alone_leave_the_environment_open(tmp_path) -> None:
    robot = write(tmp_path, "youbot.yaml", YOUBOT)
    code, _, stderr = run("resolve", MAPPING, "--capabilities", robot, "-o", tmp_path / "b")
    assert code == 1
    assert "open choice: Environment: exactly one of Room, Corridor" in stderr
    assert not (tmp_path / "b").exists()


def test_a_selection_against_the_robot_is_refused_naming_both(tmp_path) -> None:
    robot = write(tmp_path, "roomba.yaml", ROOMBA)
    code, _, stderr = run(
        "resolve", MAPPING, "--capabilities", robot, "--features", "Stereo,Room", "-o", tmp_path
    )
    assert code == 1
    assert stderr.startswith("--features:1:1: error: feature Stereo is selected, but the robot's")
    assert f"capability sensors: depth_camera ({robot}:2:1) deselects Stereo" in stderr


def test_two_cameras_select_both_and_the_feature_model_refuses(tmp_path) -> None:
    robot = write(tmp_path, "both.yaml", "base: youbot\nsensors: [stereo_camera, depth_camera]\n")
    code, _, stderr = run(
        "resolve", MAPPING, "--capabilities", robot, "--features", "Room", "-o", tmp_path / "b"
    )
    assert code == 1
    assert "PerceptionSensor: exactly one of Stereo, Depth" in stderr
    assert f"{robot}:2:1: error: invalid selection" in stderr


def test_a_capability_of_the_wrong_kind_is_located_in_the_robot_file(tmp_path) -> None:
    robot = write(tmp_path, "odd.yaml", "base: 3\nonboard_pc: yes please\n")
    code, _, stderr = run("resolve", MAPPING, "--capabilities", robot, "--features", "Room")
    assert code == 1
    lines = stderr.splitlines()
    assert lines[0].startswith(f"{robot}:1:1: error: capability base is 3, but the feature")
    assert "'base = \"youbot\"'" in lines[0] and "expected a string" in lines[0]
    assert lines[-1].startswith(f"{robot}:2:1: error: capability onboard_pc is yes please")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("- base\n", "1:1: error: a capability file is a mapping"),
        ("base: [youbot, {x: 1}]\n", "1:7: error: capability base: expected a string"),
        ("base: null\n", "1:7: error: capability base: expected a string"),
        ("2nd: true\n", "1:1: error: capability name '2nd' is not an identifier"),
        ("base: youbot\nbase: roomba\n", "2:1: error: capability base given twice"),
        # was: "capability name [ScalarNode(tag='tag:yaml.org,2002:str', ...)]"
        ("? [a, b]\n: c\n", "1:3: error: capability name: a sequence is not an identifier"),
        ("base: [youbot\n", "error: invalid YAML"),
        # were tracebacks: a tag safe YAML has no constructor for, a scalar that does not
        # convert to its tag
        (
            "base: !!python/name:os.system ''\n",
            "1:7: error: capability base: expected a string, number, true/false or a list of "
            "them (could not determine a constructor for the tag "
            "'tag:yaml.org,2002:python/name:os.system')",
        ),
        ("sensors: [a, !!int x]\n", "1:10: error: capability sensors: expected a string"),
        ("built: !!timestamp 2024-13-01\n", "(month must be in 1..12)"),
        # were "expected a string ..." at each member, or with no word of what was given
        ("sensors: !!set {a, b}\n", "1:10: error: capability sensors: a set (!!set) is not a list"),
        ("built: 2024-01-01\n", "(got a date or time: quote it to give a string)"),
        ("base: !!binary aGk=\n", "them (got binary data)"),
        ("sensors: []\n", "them (got an empty list)"),
        ("sensors: [a, [b]]\n", "them (got a list in the list)"),
        ("range: .inf\n", "them (got an infinite or not-a-number value)"),
        # was an internal RecursionError
        ("base: &a {x: *a}\n", "1:7: error: invalid YAML: a recursive alias (a node that holds"),
    ],
)
def test_bad_capability_files_are_located(tmp_path, text: str, expected: str) -> None:
    with pytest.raises(ModelError) as info:
        load_capabilities(write(tmp_path, "robot.yaml", text))
    assert expected in str(info.value.diagnostics[0])


def test_a_product_file_names_its_capability_file(tmp_path, line) -> None:
    write(tmp_path, "youbot.yaml", YOUBOT)
    product = write(tmp_path, "p.yaml", "product: p\ncapabilities: youbot.yaml\nfeatures: [Room]\n")
    selection = load_selection_file(product)
    assert selection.capabilities is not None
    assert set(resolve(line, selection).product.features) >= {"YouBot", "Stereo", "Room"}
    missing = write(tmp_path, "q.yaml", "product: q\ncapabilities: nowhere.yaml\n")
    with pytest.raises(ModelError) as info:
        load_selection_file(missing)
    assert str(info.value.diagnostics[0]).endswith(
        "q.yaml:2:15: error: capabilities: no such file nowhere.yaml"
    )
