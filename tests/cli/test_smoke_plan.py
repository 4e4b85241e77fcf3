"""What a smoke rehearsal expects, read from a bundle alone (no ROS needed here).

The plan of the paper's product: subscribers expect exactly the publishers whose data
reaches them through the bridges, clients the node server behind any endpoint
stand-in, endpoint interfaces the peer they relay to; data clients are named and
remapped as the bundle's ROS 2 launch file says; namespaces resolve as in ROS.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from spl.cli import main
from spl.core.diagnostics import ModelError
from spl.smoke.live import LiveGraph, Row, compare
from spl.smoke.plan import join
from spl.smoke.planning import load_plan
from spl.smoke.report import table

from support.smoke_runs import ROOT, write_product


@pytest.fixture(scope="module")
def paper(tmp_path_factory):
    out = tmp_path_factory.mktemp("plan") / "bundle"
    write_product(ROOT / "product_lines" / "mapping3d", "YouBot,Stereo,AdditionalPC,Room", out)
    return load_plan(out)


def interfaces(plan) -> dict:
    return {i.id: i for i in plan.interfaces()}


def test_sources_follow_the_bridges(paper):
    found = interfaces(paper)
    assert found["MappingCloud.VisualOdometry.rgb"].sources == ("Robot.StereoVision.rgb",)
    assert found["Robot.MapOptimizer.keyframes"].sources == (
        "MappingCloud.VisualOdometry.keyframes",
    )
    # one topic, two subscribers in two containers, one source
    assert found["MappingCloud.StrategyPlanner.pose_updated"].sources == (
        "Robot.MapOptimizer.pose_updated",
    )
    endpoint = found["Robot.endpoint.sub_RGBImg"]
    (relay,) = endpoint.relays  # the one flow it carries, straight from its publisher
    assert (relay.container, relay.interface) == ("MappingCloud", "pub_RGBImg")
    assert relay.passes == ("Robot.StereoVision.rgb|",) and endpoint.required
    assert found["Robot.StereoVision.rgb"].ros_name == "/camera/rgb/image"


def test_clients_expect_the_node_server_behind_endpoint_stand_ins(paper):
    found = interfaces(paper)
    client = found["Robot.MapOptimizer.add_keyframe"]
    assert client.server == "MappingCloud.Database.add_keyframe"
    assert found["Robot.endpoint.srv_Database_add_keyframe"].forward == (
        "MappingCloud",
        "cli_Database_add_keyframe",
    )
    relay = found["MappingCloud.endpoint.cli_Database_add_keyframe"]
    assert relay.required and relay.server == "MappingCloud.Database.add_keyframe"
    assert found["MappingCloud.MapMerger.get_map"].server == "MappingCloud.Database.get_map"


def test_parameters_are_typed_and_placed_under_the_node(paper):
    (optimizer,) = [n for c in paper.containers for n in c.nodes if n.name == "MapOptimizer"]
    assert optimizer.container == "Robot" and optimizer.ros_name == "/MapOptimizer"
    assert [(p.ros_name, p.value) for p in optimizer.parameters] == [
        ("/MapOptimizer/CameraInfo", "package://stereo_cam/calibration/stereo.yaml")
    ]


def test_namespaces_and_data_clients(tmp_path):
    fleet = load_plan(write_product(ROOT / "tests" / "models" / "launch", "CloudMapping",
                                    tmp_path / "fleet"))  # fmt: skip
    nodes = {n.name: n for c in fleet.containers for n in c.nodes}
    assert nodes["Lidar"].ros_name == "/scout/Lidar"
    endpoints = {c.name: c.endpoint.ros_name for c in fleet.containers}
    assert endpoints == {"Scout": "/scout/endpoint", "Mapping": "/endpoint"}
    lidar = {p.name: p.value for p in nodes["Lidar"].parameters}
    assert lidar["skip"] == 0 and lidar["intensity"] is True and lidar["angle_min"] == -2.2
    assert lidar["filters"] == {"median": {"window": 5}, "range": [0.1, 30.0]}
    data = load_plan(write_product(ROOT / "product_lines" / "data_acquisition",
                                   "Positions,Follow,Embedded", tmp_path / "data"))  # fmt: skip
    # writers and readers are launched by the ROS 1 launch files: stand-ins by default,
    # the generated nodes themselves when the rehearsal runs the data path
    reader = {n.name: n for c in data.containers for n in c.nodes}["CommandReader"]
    assert reader.role == "launched" and reader.interfaces[0].ros_name == "/ev3/command"
    bundle = tmp_path / "data"
    generated = {n.name: n for c in load_plan(bundle, generated=True).containers
                 for n in c.nodes}  # fmt: skip
    assert generated["CommandReader"].role == "generated"
    assert load_plan(bundle).messages["ev3_msgs/Command"] == (
        "string TYPE=ev3_msgs/Command\nfloat64 duration\nfloat64 vx\nfloat64 vy\nfloat64 va\n"
        "string source\nstring route\nuint32 seq\n"
    )
    assert join("/scout", "map") == "/scout/map" and join("/scout", "/map") == "/map"


def test_live_graph_differences_become_failing_rows(paper):
    robot = paper.containers[0]
    graph = LiveGraph(
        publishers={"/stereo/left/image_raw": {"/RGBCameraL"}, "/extra": {"/Intruder"}},
        types={"/stereo/left/image_raw": "sensor_msgs/CompressedImage"},
    )
    rows = compare(robot, graph, {}, {})
    by_key = {(r.node, r.interface): r for r in rows}
    assert by_key[("RGBCameraL", "(node)")].seen == "not running"
    image = by_key[("RGBCameraL", "image")]
    assert not image.ok and "type sensor_msgs/CompressedImage" in image.seen
    intruder = by_key[("/Intruder", "(node)")]
    assert intruder.expected == "not in the model" and not intruder.ok
    assert not by_key[("StereoVision", "left")].ok  # nothing received, not registered
    lines = table([Row("Robot", "A", "b", "/t", "x", "y", True)])
    assert lines == [
        "    NODE  INTERFACE  TOPIC  EXPECTED  SEEN",
        "ok  A     b          /t     x         y",
    ]


def test_a_folder_that_is_not_a_bundle(tmp_path):
    with pytest.raises(ModelError, match=r"is not an spl bundle: no resolved\.tsm"):
        load_plan(tmp_path)
    result = CliRunner().invoke(main, ["smoke", str(tmp_path)])
    assert result.exit_code == 1
    assert result.output == f"error: {tmp_path} is not an spl bundle: no resolved.tsm\n"


def test_plan_is_read_from_the_bundle_not_the_product_line(tmp_path):
    out = write_product(ROOT / "product_lines" / "mapping3d", "YouBot,Stereo,AdditionalPC,Room",
                        tmp_path / "bundle")  # fmt: skip
    model = out / "resolved.tsm"
    model.write_text(model.read_text().replace("bridge Robot.RGBImg -> MappingCloud.RGBImg\n", ""))
    found = interfaces(load_plan(Path(out)))
    assert found["MappingCloud.VisualOdometry.rgb"].sources == ()
    assert "Robot.endpoint.sub_RGBImg" not in found


def test_an_interface_the_product_leaves_unconnected_expects_nothing(tmp_path):
    # orchard without yield mapping: PathPlanner's `subscribes yield_map : nav_msgs/...`
    # is connected by no element, so no launch remap and nothing to receive; with yield
    # mapping it is fed by the YieldMapper
    line = ROOT / "product_lines" / "orchard"
    without, with_map = tmp_path / "without", tmp_path / "with"
    write_product(line, line / "products" / "onboard_soft.yaml", without)
    write_product(line, line / "products" / "scout_yield_public.yaml", with_map)
    idle = interfaces(load_plan(without))["Harvester.PathPlanner.yield_map"]
    assert not idle.required and idle.sources == ()
    fed = interfaces(load_plan(with_map))["OrchardCloud.PathPlanner.yield_map"]
    assert fed.required and fed.sources == ("OrchardCloud.YieldMapper.yield_map",)


def test_inputs_the_model_leaves_unfed_are_worded_by_their_kind(paper, tmp_path):
    """The warehouse camera product (tests/models/line_checks/warehouse) leaves the
    localizer's scan unfed and the detector's classify unserved: each planned input
    carries resolve's verdict in the rehearsal's word for its kind, a client with no
    server to answer it expects no answer, and the stand-ins are told each interface's
    role."""
    warehouse = ROOT / "tests" / "models" / "line_checks" / "warehouse"
    plan = load_plan(write_product(warehouse, "CameraSensing,Detection", tmp_path / "bundle"))
    found = interfaces(plan)
    scan, classify = found["Amr.Localizer.scan"], found["Cloud.Detector.classify"]
    assert scan.gap == "unfed in the model (SPL045)" and scan.required
    assert classify.gap == "unserved in the model (SPL046)" and not classify.required
    assert found["Amr.Localizer.odom"].gap.startswith("fed from outside the architecture: ")
    assert found["Amr.Localizer.pose"].gap == ""
    told = {
        (container, node["id"].split(".")[1], i["name"]): i["kind"]
        for container, described in plan.stand_in_description(tmp_path)["containers"].items()
        for node in described["nodes"].values()
        for i in node["interfaces"]
    }
    assert told[("Amr", "Localizer", "scan")] == "subscriber"
    assert told[("Amr", "Localizer", "pose")] == "publisher"
    assert told[("Cloud", "Detector", "classify")] == "client"
    served = paper.stand_in_description(tmp_path)["containers"]["MappingCloud"]["nodes"]
    database = next(n for n in served.values() if n["id"] == "MappingCloud.Database")
    assert {i["kind"] for i in database["interfaces"]} == {"server"}
