"""The .tsm language: what the examples of docs/tsm.md and the shipped models mean once parsed,
and that the printer writes every model back to text that parses to the same model."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from spl.cli import main
from spl.core.emf_compare import differences
from spl.dsl.tsm import language as tsm
from spl.dsl.tsm.printer import expression_text, print_model

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "tests" / "models" / "tsm"
MAPPING = ROOT / "product_lines" / "mapping3d" / "mapping.tsm"


def by_name(elements: Any, name: str) -> Any:
    found = [e for e in elements if e.name == name]
    assert len(found) == 1, f"{name}: {[e.name for e in elements]}"
    return found[0]


def container(system: Any, name: str) -> Any:
    return by_name(system.containers, name)


def node(system: Any, container_name: str, node_name: str) -> Any:
    return by_name(container(system, container_name).nodes, node_name)


def interface(system: Any, container_name: str, node_name: str, name: str) -> Any:
    return by_name(node(system, container_name, node_name).interfaces, name)


# -- docs/tsm.md, first example ------------------------------------------------------
@pytest.fixture(scope="module")
def spec_mapping() -> Any:
    return tsm.parse_file(MODELS / "spec_mapping.tsm")


def test_spec_example_containers_and_endpoints(spec_mapping: Any) -> None:
    system = spec_mapping
    assert system.name == "Mapping3D"
    robot, cloud = system.containers
    assert (robot.eClass.name, cloud.eClass.name) == ("RobotContainer", "CloudContainer")
    assert cloud.group == "mappers" and cloud.size is None
    endpoint = robot.endpoint
    assert (endpoint.robotId, endpoint.url, endpoint.user, endpoint.passwordEnv) == (
        "robot_1",
        "wss://cloud.example.org:9000/",
        "mapper",
        "RCE_PASSWORD",
    )
    # every container has an endpoint; a cloud one carries no credentials
    assert cloud.endpoint is not None
    assert (cloud.endpoint.robotId, cloud.endpoint.passwordEnv) == (None, None)


def test_spec_example_nodes_topics_and_parameters(spec_mapping: Any) -> None:
    system = spec_mapping
    robot = container(system, "Robot")
    assert [t.name for t in robot.topics] == ["RGBImg", "DepthImg", "Twist"]
    assert by_name(robot.topics, "Twist").rosName == "/cmd_vel"
    assert by_name(robot.topics, "Twist").type == "geometry_msgs/Twist"
    assert by_name(container(system, "MappingCloud").topics, "Keyframes").rosName == "/Keyframes"
    camera = node(system, "Robot", "DepthCamera")
    assert camera.optional and camera.sharing.name == "private"
    assert (camera.package, camera.executable) == ("openni2_camera", "openni2_camera_node")
    driver = node(system, "Robot", "RobotDriver")
    assert not driver.optional
    params = {p.name: (p.type.name, p.value) for p in driver.parameters}
    assert params == {"port": ("string", "/dev/ttyUSB0"), "rate": ("double", "20.0")}
    database = node(system, "MappingCloud", "Database")
    assert database.sharing.name == "protected"
    assert sum(len(c.nodes) for c in system.containers) == 4


def test_spec_example_interface_bindings(spec_mapping: Any) -> None:
    system = spec_mapping
    rgb = interface(system, "Robot", "DepthCamera", "rgb")
    assert rgb.eClass.name == "Publisher"
    assert rgb.topic is by_name(container(system, "Robot").topics, "RGBImg")
    assert rgb.type == "sensor_msgs/Image"
    cmd = interface(system, "Robot", "RobotDriver", "cmd")
    assert cmd.eClass.name == "Subscriber" and cmd.topic.name == "Twist"
    add = interface(system, "MappingCloud", "Database", "add_keyframe")
    assert (add.eClass.name, add.type, add.rosName) == (
        "ServiceServer",
        "rapyuta_msgs/AddKeyframe",
        "/db/add_keyframe",
    )
    store = interface(system, "MappingCloud", "MapOptimizer", "store")
    assert store.eClass.name == "ServiceClient"
    assert store.server is add and store.type == "rapyuta_msgs/AddKeyframe"
    info = by_name(node(system, "MappingCloud", "MapOptimizer").parameters, "CameraInfo")
    assert info.value == "package://rapyuta_mapping/cam/default.yaml"


def test_spec_example_bridge_is_endpoint_interfaces_and_a_connection(spec_mapping: Any) -> None:
    system = spec_mapping
    robot, cloud = container(system, "Robot"), container(system, "MappingCloud")
    (sub,) = robot.endpoint.interfaces
    (pub,) = cloud.endpoint.interfaces
    assert (sub.eClass.name, sub.name, sub.topic, sub.type) == (
        "Subscriber",
        "sub_RGBImg",
        by_name(robot.topics, "RGBImg"),
        "sensor_msgs/Image",
    )
    assert (pub.eClass.name, pub.name, pub.topic) == (
        "Publisher",
        "pub_RGBImg",
        by_name(cloud.topics, "RGBImg"),
    )
    (connection,) = system.connections
    assert connection.source is sub and connection.target is pub
    assert (connection.srcLine, connection.srcCol) == (43, 1)


# -- docs/tsm.md, second example (data acquisition) ------------------------------------
def test_spec_data_acquisition_example() -> None:
    system = tsm.parse_file(MODELS / "spec_data.tsm")
    assert system.name is None
    second, degrees = system.dataTypes
    assert [(f.name, f.type.name) for f in second.fields] == [("lat", "double"), ("lon", "double")]
    (transform,) = system.transforms
    assert (transform.input, transform.output) == (second, degrees)
    assert [a.field for a in transform.assignments] == ["lat", "lon"]
    lat = transform.assignments[0].expression
    assert (lat.eClass.name, lat.operator) == ("BinaryExpression", "/")
    assert (lat.left.record, lat.left.field) == ("", "lat")
    assert lat.right.value == "3600.0"
    cloud, rover = system.containers
    (store,) = cloud.stores
    assert store.raw is second and not store.optional
    (refinement,) = store.refinements
    assert refinement.output is degrees and refinement.transform is transform
    assert refinement.period == 5.0
    writer, reader = rover.nodes
    assert writer.eClass.name == "Writer" and reader.eClass.name == "Reader"
    assert writer.store is store and writer.dataType is second
    assert (writer.package, writer.executable) == (None, None)
    (records,) = writer.interfaces
    assert (records.eClass.name, records.name, records.topic.name) == (
        "Subscriber",
        "records",
        "GpsSeconds",
    )
    assert records.type == "rover_msgs/PositionInSecond"
    assert reader.store is store and reader.dataType is degrees and reader.period == 1.0
    (published,) = reader.interfaces
    assert (published.eClass.name, published.topic.name) == ("Publisher", "GpsDeg")
    assert cloud.endpoint is not None and rover.endpoint is not None


# -- the shipped mapping3d model --------------------------------------------------------
def test_mapping3d_model() -> None:
    system = tsm.parse_file(MAPPING)
    assert [c.name for c in system.containers] == ["Robot", "MappingCloud"]
    assert container(system, "MappingCloud").group == "mappers"
    assert container(system, "Robot").endpoint.passwordEnv == "RCE_PASSWORD"
    nodes = [n for c in system.containers for n in c.nodes]
    assert len(nodes) == 12
    assert sum(len(c.topics) for c in system.containers) == 9
    assert sum(len(n.interfaces) for n in nodes) == 28
    assert {n.name for n in nodes if n.optional} == {
        "DepthCamera",
        "RGBCameraL",
        "RGBCameraR",
        "StereoVision",
    }
    # bridges: three topic bridges and the next_target service bridge
    assert len(system.connections) == 4
    robot_endpoint = {i.name for i in container(system, "Robot").endpoint.interfaces}
    assert robot_endpoint == {
        "sub_RGBImg",
        "sub_DepthImg",
        "pub_PoseUpdated",
        "srv_StrategyPlanner_next_target",
    }
    client = interface(system, "Robot", "RobotController", "next_target")
    assert client.server.name == "srv_StrategyPlanner_next_target"
    assert client.server.rosName == "/exploration/next_target"
    caller = by_name(
        container(system, "MappingCloud").endpoint.interfaces, "cli_StrategyPlanner_next_target"
    )
    assert caller.server is interface(system, "MappingCloud", "StrategyPlanner", "next_target")
    stereo = node(system, "Robot", "StereoVision")
    assert all(i.topic is None and i.type == "sensor_msgs/Image" for i in stereo.interfaces)
    info = by_name(node(system, "MappingCloud", "MapOptimizer").parameters, "CameraInfo")
    assert (info.type.name, info.value) == ("string", None)


def test_spl_check_mapping3d_prints_summary() -> None:
    result = CliRunner().invoke(main, ["check", str(MAPPING)])
    assert result.exit_code == 0, result.output
    assert result.output.strip() == (
        f"{MAPPING}: ok: 2 containers, 12 nodes, 9 topics, 28 interfaces, 4 bridges"
    )


# -- everything at once -----------------------------------------------------------------
def test_every_construct_means_what_it_says() -> None:
    system = tsm.parse_file(MODELS / "everything.tsm")
    rover, lab, other = system.containers
    assert rover.namespace == "/rover7" and lab.namespace == "lab"
    assert (lab.group, lab.size, lab.cpu, lab.memory, lab.bandwidth) == ("labs", 2, 4, 2048, 100)
    assert (other.cpu, other.size, other.group) == (1, None, None)
    lidar = by_name(rover.nodes, "Lidar")
    assert lidar.sharing.name == "public"
    assert lidar.executable == "lidar_node.py" and lidar.args == "--port /dev/ttyUSB0 --rate=10"
    values = {p.name: p.value for p in lidar.parameters}
    assert values == {
        "port": 'tab\there "quoted" back\\slash',
        "rate": "-20",
        "gain": "1e-05",
        "enabled": "false",
        "config": "{frame: laser, ranges: [0.1, 30]}",
        "later": None,
    }
    assert by_name(lidar.interfaces, "reset").rosName == "/reset"
    assert by_name(lidar.interfaces, "reset_self").server is by_name(lidar.interfaces, "reset")
    assert by_name(rover.topics, "Samples").rosName == "samples/raw"
    # two clients in Rover bridged to one server share one stand-in and one connection
    helper = by_name(rover.nodes, "Helper")
    assert helper.optional and helper.sharing.name == "protected"
    stand_in = by_name(lidar.interfaces, "plan").server
    assert by_name(helper.interfaces, "plan").server is stand_in
    assert stand_in.name == "srv_Planner_plan" and stand_in.rosName == "/move_base/plan"
    assert [i.name for i in rover.endpoint.interfaces] == [
        "sub_Scan",
        "srv_Planner_plan",
        "srv_Clock_sync",
    ]
    assert [i.name for i in lab.endpoint.interfaces] == [
        "pub_Scan",
        "cli_Planner_plan",
        "cli_Clock_sync",
    ]
    assert len(system.connections) == 4
    spare = by_name(lab.stores, "Spare")
    assert spare.optional and list(spare.refinements) == []
    built = by_name(rover.nodes, "BuiltWriter")
    assert (built.package, built.executable, built.args) == (
        "sample_writer",
        "sample_writer",
        "--verbose",
    )
    reader = by_name(rover.nodes, "SummaryReader")
    assert reader.optional and reader.period == 0.25
    assert [(p.name, p.value) for p in reader.parameters] == [("verbose", "true")]


def test_expressions_build_the_expected_tree() -> None:
    system = tsm.parse_file(MODELS / "everything.tsm")
    mean, flag, gap = (a.expression for a in system.transforms[0].assignments)
    # `... + if(ok, pi, e)`: left-associative sums, constants become numbers
    assert mean.operator == "+"
    call = mean.right
    assert call.eClass.name == "CallExpression" and call.function == "if"
    assert [float(a.value) for a in call.arguments[1:]] == [math.pi, math.e]
    # `or` binds loosest, then `and`, then `not`, then comparisons
    assert flag.operator == "or"
    assert flag.left.operator == "and" and flag.left.left.operator == "not"
    assert flag.left.right.operator == ">="
    assert gap.left.left.record == "next" and gap.left.left.field == "timestamp"
    assert gap.right.left.record == "prev"
    assert expression_text(flag) == (
        "not ok and x >= 1 or n != 2 and not (x < 0.5 or x == 3) and n <= 7 and x > -1000.0"
    )
    assert expression_text(mean).startswith("-(x + n) * 2 / 3 % 4 - -x + abs(x)")


# -- printer round trip -----------------------------------------------------------------
def shipped_and_test_models() -> list[Path]:
    found = sorted((ROOT / "tests" / "models").rglob("*.tsm"))
    found += sorted((ROOT / "product_lines").rglob("*.tsm"))
    return found


@pytest.mark.parametrize("path", shipped_and_test_models(), ids=lambda p: str(p.relative_to(ROOT)))
def test_printer_round_trip(path: Path) -> None:
    model = tsm.parse_file(path)
    text = print_model(model)
    again = tsm.parse_text(text, "printed.tsm")
    assert list(differences(model, again)) == []
    assert print_model(again) == text  # deterministic, and a fixed point


def test_printer_omits_defaults_and_prints_bridges() -> None:
    text = print_model(tsm.parse_file(MODELS / "spec_mapping.tsm"))
    assert "topic Keyframes : rapyuta_msgs/Keyframe\n" in text
    assert "sharing private" not in text and "sharing protected" in text
    assert text.rstrip().endswith("bridge Robot.RGBImg -> MappingCloud.RGBImg")
    assert 'password env "RCE_PASSWORD"' in text


def test_normalize_endpoints_restores_the_order_parsing_gives() -> None:
    system = tsm.parse_file(MAPPING)
    endpoint = container(system, "Robot").endpoint
    expected = [i.name for i in endpoint.interfaces]
    reversed_interfaces = list(reversed(endpoint.interfaces))
    endpoint.interfaces.clear()
    endpoint.interfaces.extend(reversed_interfaces)
    again = tsm.parse_text(print_model(system), "printed.tsm")
    assert list(differences(system, again)) != []
    tsm.normalize_endpoints(system)
    assert [i.name for i in endpoint.interfaces] == expected
    assert list(differences(system, again)) == []


def test_canonical_endpoint_names() -> None:
    system = tsm.parse_file(MAPPING)
    topic = by_name(container(system, "Robot").topics, "RGBImg")
    server = interface(system, "MappingCloud", "Database", "get_map")
    assert tsm.endpoint_subscriber_name(topic) == "sub_RGBImg"
    assert tsm.endpoint_publisher_name(topic) == "pub_RGBImg"
    assert tsm.endpoint_server_name(server) == "srv_Database_get_map"
    assert tsm.endpoint_client_name(server) == "cli_Database_get_map"


@pytest.mark.parametrize(
    "features", ["YouBot,Stereo,AdditionalPC,Room", "Roomba,Depth,Corridor"], ids=str
)
def test_printer_round_trip_of_resolved_products(features: str) -> None:
    """Resolved architectures (migrated nodes, rewired endpoints) print back exactly."""
    from spl.resolver.resolution.engine import resolve
    from spl.resolver.resolution.product_line import load_product_line
    from spl.resolver.resolution.product_selection import selection_from_list

    resolution = resolve(load_product_line(MAPPING.parent), selection_from_list(features))
    system = resolution.product.system
    text = print_model(system)
    assert list(differences(system, tsm.parse_text(text, "resolved.tsm"))) == []
    if "AdditionalPC" in features:
        assert "bridge Robot.MapOptimizer.add_keyframe -> MappingCloud.Database.add_keyframe" in (
            text
        )
