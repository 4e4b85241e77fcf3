"""Engine behaviour: conflicts, `not selected` elements, attributes, sharing, selection
errors, the example of docs/rm.md, and the command line's determinism and atomicity."""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from spl.cli import main
from spl.core.diagnostics import ModelError
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import apply_overrides, selection_from_list

from support.one_feature_line import MAP_SERVER_BRIDGE, MAP_SERVER_TSM, one_feature_line

MODELS = Path(__file__).parents[1] / "models"
CONFLICTS = MODELS / "resolver" / "conflicts"
SPEC = MODELS / "rm" / "spec_example"
MAPPING = Path(__file__).resolve().parents[2] / "product_lines" / "mapping3d"


@pytest.fixture(scope="module")
def conflicts():
    return load_product_line(CONFLICTS)


def errors_of(line, features: str, sharing=(), settings=()) -> list[str]:
    selection = apply_overrides(selection_from_list(features), list(sharing), list(settings))
    with pytest.raises(ModelError) as caught:
        resolve(line, selection)
    return [str(d) for d in caught.value.diagnostics]


def nodes(line, features: str, sharing=(), settings=()):
    selection = apply_overrides(selection_from_list(features), list(sharing), list(settings))
    system = resolve(line, selection).product.system
    return {n.name: n for c in system.containers for n in c.nodes}


@pytest.mark.parametrize(
    ("features", "kind", "line_no"),
    [
        ("Fast,Slow", "implementation", 10),
        ("Remote,Local", "migration target", 17),
    ],
)
def test_conflicts_name_both_elements(conflicts, features, kind, line_no):
    message = errors_of(conflicts, features)[0]
    assert message.startswith(f"{CONFLICTS / 'conflicts.rm'}:{line_no}:5: error: conflict:")
    assert f"gives {kind}" in message
    assert "'when Fast selected'" in message or "'when Remote selected'" in message
    assert "conflicts.rm:" in message.split("but", 1)[1]


def test_parameter_conflict(conflicts):
    messages = errors_of(conflicts, "Fast,Slow")
    assert any("gives value 1.5 to Driver.rate" in m and "50.0" in m for m in messages)


def test_not_selected_element_and_attribute_values(conflicts):
    driver = nodes(conflicts, "Fast", settings=["Fast.rate=75"])["Driver"]
    params = {p.name: p.value for p in driver.parameters}
    assert params == {"rate": "75.0", "port": "/dev/ttyACM0"}
    assert nodes(conflicts, "Manual")["Driver"].parameters[1].value == "/dev/ttyUSB0"
    assert "Teleop" in nodes(conflicts, "Manual") and "Teleop" not in nodes(conflicts, "Slow")


def test_attribute_errors_are_located(conflicts):
    (bad_type,) = errors_of(conflicts, "Fast", settings=["Fast.rate=fast"])
    assert bad_type == "--set:1:1: error: attribute Fast.rate is double, got 'fast'"
    (unknown,) = errors_of(conflicts, "Fast", settings=["Fast.speed=1"])
    assert "unknown feature attribute Fast.speed" in unknown


@pytest.mark.parametrize(
    ("setting", "value"),
    [  # each was read as YAML: a bool, an int, a date, nothing; 1e3 a string
        ("Fast.name=off", "off"),
        ("Fast.name=123", "123"),
        ("Fast.name=2024-01-01", "2024-01-01"),
        ("Fast.name=#3", "#3"),
        ("Fast.rate=1e3", "1000.0"),
        ("Fast.rate=75", "75.0"),
    ],
)
def test_set_reads_the_value_by_the_attributes_type(tmp_path, setting, value):
    """`--set F.attr=TEXT` is read as the attribute's declared type, not as YAML."""
    line = tmp_path / "line"
    shutil.copytree(CONFLICTS, line)
    fm = next(line.glob("*.fm"))
    fm.write_text(
        fm.read_text().replace(
            "attribute rate : double = 50.0",
            'attribute rate : double = 50.0 attribute name : string = "x"',
        )
    )
    conflicts = load_product_line(line)
    selection = apply_overrides(selection_from_list("Fast"), [], [setting])
    attributes = resolve(conflicts, selection).product.attributes
    assert str(attributes[setting.split("=")[0]]) == value


def test_set_refuses_text_that_is_not_of_the_attributes_type(conflicts):
    for text in ("0x10", "true", "1.5.2", "nan"):
        (message,) = errors_of(conflicts, "Fast", settings=[f"Fast.rate={text}"])
        assert message == f"--set:1:1: error: attribute Fast.rate is double, got {text!r}"


def test_sharing_default_and_override(conflicts):
    assert nodes(conflicts, "Shared")["Planner"].sharing.name == "protected"
    assert nodes(conflicts, "Shared", sharing=["Shared=public"])["Planner"].sharing.name == "public"
    (message,) = errors_of(conflicts, "Slow", sharing=["Slow=public"])
    assert "Slow, which has no sharing attribute" in message


def test_bad_selections_are_explained(conflicts):
    mapping = load_product_line(MAPPING)
    (unknown,) = errors_of(mapping, "YouBot,Stereo,Room,Hovercraft")
    assert unknown == "--features:1:1: error: unknown feature 'Hovercraft'"
    (excluded,) = errors_of(mapping, "Roomba,Depth,Room,AdditionalPC")
    assert "Roomba excludes AdditionalPC" in excluded and "mapping.fm:" in excluded
    open_choices = errors_of(mapping, "YouBot,Room")
    assert len(open_choices) == 1 and "exactly one of Stereo, Depth" in open_choices[0]


def test_spec_section_4_example_resolves():
    line = load_product_line(SPEC)
    assert [e.feature.name for e in line.rm.elements] == [
        "Mapping",
        "YouBot",
        "Stereo",
        "AdditionalPC",
        "Logging",
        "Room",
        "Room",
    ]
    room = nodes(line, "YouBot,Stereo,Room,Logging", settings=["Logging.rate=5.0"])
    assert room["StrategyPlanner"].executable == "room_strategy"
    assert room["LogWriter"].parameters[0].value == "5.0"
    assert room["MapOptimizer"].eContainer().name == "Robot"
    corridor = nodes(line, "Roomba,Depth,Corridor")
    assert corridor["StrategyPlanner"].executable == "corridor_strategy"  # `not selected`
    assert "LogWriter" not in corridor


def run(*args):
    return CliRunner().invoke(main, list(args))


def digest(folder: Path) -> dict[str, str]:
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def test_resolve_is_deterministic(tmp_path):
    product = str(MAPPING / "products" / "youbot_stereo_room.yaml")
    first, second = tmp_path / "a", tmp_path / "b"
    assert run("resolve", str(MAPPING), "--features", product, "-o", str(first)).exit_code == 0
    assert run("resolve", str(MAPPING), "--features", product, "-o", str(second)).exit_code == 0
    assert digest(first) == digest(second)
    assert {"manifest.json", "resolved.tsm", "resolved.xmi"} <= set(digest(first))


def test_failing_resolve_leaves_nothing(tmp_path):
    out = tmp_path / "bundle"
    result = run("resolve", str(MAPPING), "--features", "Roomba,AdditionalPC", "-o", str(out))
    assert result.exit_code == 1
    assert "Roomba excludes AdditionalPC" in result.output
    assert list(tmp_path.iterdir()) == []


def test_failed_resolve_keeps_the_previous_bundle(tmp_path):
    out = tmp_path / "bundle"
    assert (
        run("resolve", str(MAPPING), "--features", "YouBot,Depth,Room", "-o", str(out)).exit_code
        == 0
    )
    before = digest(out)
    assert run("resolve", str(MAPPING), "--features", "YouBot", "-o", str(out)).exit_code == 1
    assert digest(out) == before and [p.name for p in tmp_path.iterdir()] == ["bundle"]


def test_out_never_replaces_what_spl_did_not_write(tmp_path):
    """`-o` naming the product line's own folder (reported: its models were deleted, exit
    0), a folder of the user's, a file or a symbolic link is refused, exit 1, nothing
    touched; an earlier bundle and an empty folder are replaced."""
    line = tmp_path / "mapping3d"
    shutil.copytree(MAPPING, line)
    before = digest(line)
    features = ["resolve", str(line), "--features", "YouBot,Depth,Room", "-o"]
    notes = tmp_path / "notes"
    notes.mkdir()
    (notes / "todo.txt").write_text("keep me\n")
    a_file = tmp_path / "file.txt"
    a_file.write_text("keep me\n")
    link = tmp_path / "link"
    link.symlink_to(notes)
    for out, reason in [
        (line, "is not a bundle written by spl"),
        (line / "products", "is not a bundle written by spl"),
        (notes, "is not a bundle written by spl"),
        (a_file, "is not a folder"),
        (link, "is a symbolic link"),
    ]:
        result = run(*features, str(out))
        assert result.exit_code == 1, result.output
        assert f"{out}: error: " in result.output and reason in result.output
    assert digest(line) == before
    assert (notes / "todo.txt").read_text() == "keep me\n" == a_file.read_text()
    assert link.is_symlink()
    # what may be replaced: an empty folder, then the bundle spl wrote there
    empty = tmp_path / "empty"
    empty.mkdir()
    assert run(*features, str(empty)).exit_code == 0
    assert (
        run("resolve", str(line), "--features", "YouBot,Stereo,Room", "-o", str(empty)).exit_code
        == 0
    )
    assert "Stereo" in json.loads((empty / "manifest.json").read_text())["features"]


def test_resolved_tsm_checks_again(tmp_path):
    out = tmp_path / "bundle"
    run("resolve", str(MAPPING), "--features", "YouBot,Stereo,AdditionalPC,Room", "-o", str(out))
    result = run("check", str(out / "resolved.tsm"))
    assert result.exit_code == 0, result.output


def test_explain_says_why(tmp_path):
    result = run(
        "explain", str(MAPPING), "--features", "YouBot,Stereo,AdditionalPC,Room", "MapOptimizer"
    )
    assert result.exit_code == 0
    assert "MapOptimizer: present in container Robot" in result.output
    assert "migrated: from MappingCloud to Robot by 'when AdditionalPC selected'" in result.output
    absent = run(
        "explain", str(MAPPING), "--features", "YouBot,Stereo,AdditionalPC,Room", "DepthCamera"
    )
    assert "removed: optional node that no active resolution element requires" in absent.output
    assert "mapping.tsm:" in absent.output


def explain(element: str) -> list[str]:
    result = run("explain", str(MAPPING), "--features", "YouBot,Stereo,AdditionalPC,Room", element)
    assert result.exit_code == 0, result.output
    return result.output.splitlines()


def test_explain_a_topic_explains_it_in_every_container_that_has_it():
    # was: only Robot.RGBImg's trace entry; MappingCloud.RGBImg was refused by its name
    lines = explain("RGBImg")
    assert lines[0] == "Robot.RGBImg: topic present, /camera/rgb/image (sensor_msgs/Image)"
    assert lines[1].startswith("  Robot.RGBImg: kept: rgb of StereoVision is connected to it")
    assert lines[2] == "MappingCloud.RGBImg: topic present, /camera/rgb/image (sensor_msgs/Image)"
    assert lines[3].startswith("  nothing in this product decided about it")
    assert lines[3].endswith("mapping.tsm:60:11)")
    assert explain("MappingCloud.RGBImg") == lines[2:]


def test_explain_an_interface_says_what_it_is_bound_to_and_why_it_moved():
    # was: "no element named 'MapOptimizer.keyframes'" (exit 2)
    lines = explain("MapOptimizer.keyframes")
    assert lines[0] == "MapOptimizer.keyframes: subscribes to topic Robot.Keyframes"
    assert lines[1].startswith("  MapOptimizer: migrated: from MappingCloud to Robot by")
    # the node's other decisions are not about its interfaces; its flows are
    assert lines[2:] == [
        "  fed by MappingCloud.VisualOdometry.keyframes through MappingCloud -> Robot"
    ]
    assert explain("Robot.MapOptimizer.keyframes") == lines
    client = explain("MapOptimizer.add_keyframe")
    assert client[:2] == [
        "MapOptimizer.add_keyframe: calls Robot.endpoint.srv_Database_add_keyframe",
        "  MapOptimizer.add_keyframe: bridged: to Database.add_keyframe in MappingCloud through "
        "an endpoint stand-in in Robot, as MapOptimizer is migrated to Robot by 'when "
        f"AdditionalPC selected' ({MAPPING / 'mapping.rm'}:44:1) ({MAPPING / 'mapping.rm'}:45:5)",
    ]
    assert client[-1] == (
        "  answered by MappingCloud.Database.add_keyframe through Robot -> MappingCloud"
    )
    assert explain("DepthCamera.rgb") == [
        "DepthCamera.rgb: not in this product",
        "  DepthCamera: removed: optional node that no active resolution element requires or "
        f"transforms ({MAPPING / 'mapping.tsm'}:17:19)",
    ]


def test_explain_says_how_a_node_stands_when_asked_by_its_template_place():
    # were: only the decisions, with no line saying where the node is or that it is gone
    moved = explain("MappingCloud.MapOptimizer")
    assert moved[0] == "MapOptimizer: present in container Robot"
    assert moved == explain("MapOptimizer")
    assert explain("DepthCamera")[:2] == [
        "DepthCamera: not in this product",
        "  DepthCamera: removed: optional node that no active resolution element requires or "
        f"transforms ({MAPPING / 'mapping.tsm'}:17:19)",
    ]


def test_explain_refuses_a_bare_interface_name_and_names_the_ones_meant():
    args = ["explain", str(MAPPING), "--features", "YouBot,Stereo,AdditionalPC,Room"]
    result = run(*args, "keyframes")
    assert result.exit_code == 2
    assert "did you mean MapOptimizer.keyframes, VisualOdometry.keyframes?" in result.output


def test_explain_answers_for_a_feature_left_out_and_says_which_capability_did(tmp_path):
    # was: "no element named 'Roomba'" (exit 2) for any feature the product does not select
    args = ["explain", str(MAPPING), "--features", "YouBot,Stereo,AdditionalPC,Room", "Roomba"]
    result = run(*args)
    assert result.exit_code == 0
    assert result.output.splitlines()[0] == "Roomba: feature not selected"
    robot = MAPPING / "fleets" / "robots" / "youbot_1.yaml"
    chosen = run("explain", str(MAPPING), "--capabilities", str(robot), "--features", "Room",
                 "Roomba")  # fmt: skip
    lines = chosen.output.splitlines()
    assert lines[0] == "Roomba: feature not selected"
    assert lines[1].startswith(f"  capability base: youbot ({robot}:3:1) deselects Roomba: ")
    assert run(*args[:-1], "Nope").exit_code == 2


def test_a_new_topic_under_a_ros_name_taken_by_another_type_is_an_error(tmp_path):
    # was resolved and validated: Sonar's Range and Lidar's LaserScan were both /scan; then
    # refused per product (SPL044) while spl check passed; now refused with the .rm
    line = tmp_path / "line"
    line.mkdir()
    (line / "l.tsm").write_text(
        "system D\nrobot container R {\n"
        '    endpoint robot_id "r1" url "wss://x.example.org:9000/" user "u" password env "P"\n'
        '    topic Scan : sensor_msgs/LaserScan name "/scan"\n'
        "    node Lidar { implementation a/b publishes scan -> Scan }\n"
        "    optional node Sonar { implementation a/c publishes range : sensor_msgs/Range }\n"
        "    node Planner { implementation a/d subscribes scan <- Scan }\n}\n"
    )
    (line / "l.fm").write_text("feature model D\nroot D { optional Sonars }\n")
    (line / "l.rm").write_text(
        'resolution model D\ntsm "l.tsm"\nfm "l.fm"\nwhen Sonars selected {\n'
        "    require Sonar\n"
        '    connect Sonar.range to new topic Ranges : sensor_msgs/Range name "/scan"\n}\n'
    )
    refusal = (
        f"{line / 'l.rm'}:6:5: error: new topic Ranges is /scan in container R, as topic Scan "
        f"is ({line / 'l.tsm'}:4:11), but carries sensor_msgs/Range, not "
        "sensor_msgs/LaserScan: one ROS topic carries one message type\n"
    )
    result = run("resolve", str(line), "--features", "Sonars", "-o", str(tmp_path / "out"))
    assert (result.exit_code, result.stderr) == (1, refusal)
    assert not (tmp_path / "out").exists()
    checked = run("check", str(line))
    assert checked.exit_code == 1 and refusal in checked.stderr


@pytest.mark.parametrize("bridged", [False, True])
def test_a_cloud_container_no_robot_reaches_is_warned_about(tmp_path, bridged):
    # was silent: its nodes got a launch file, and neither rapyuta/ nor kubernetes/
    # deployed them (reported by a from-scratch user test)
    bridge = MAP_SERVER_BRIDGE if bridged else ""
    line = one_feature_line(tmp_path / "line", MAP_SERVER_TSM + bridge)
    result = run("resolve", str(line), "--features", "M", "-o", str(tmp_path / "out"))
    assert result.exit_code == 0, result.output
    kustomization = (tmp_path / "out" / "kubernetes" / "kustomization.yaml").read_text()
    # the namespace (restricted, default deny) is always there; instances only when reached
    resources = yaml.safe_load(kustomization)["resources"]
    if bridged:
        assert "SPL048" not in result.stderr
        assert resources != ["namespace.yaml"] and "namespace.yaml" in resources
    else:
        assert result.stderr.splitlines()[-1] + "\n" == (
            f"{line / 'm.tsm'}:6:17: warning: cloud container C is linked to no robot container "
            "(no bridge joins it to one, directly or through other clouds): rapyuta/ and "
            "kubernetes/ deploy none of its nodes (MapServer, FleetManager); bridge it to the "
            "robot containers that use it [SPL048]\n"
        )
        assert resources == ["namespace.yaml"]
