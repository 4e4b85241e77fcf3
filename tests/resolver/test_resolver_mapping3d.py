"""The shipped mapping3d line, product by product, element by element
(docs/product-lines.md and the mapping paper's section VI)."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file

from support.architecture_view import view

LINE = Path(__file__).resolve().parents[2] / "product_lines" / "mapping3d"
CLOUD_NODES = ["VisualOdometry", "Database", "MapMerger", "StrategyPlanner"]


@pytest.fixture(scope="module")
def line():
    return load_product_line(LINE)


def product(line, name: str):
    return resolve(line, load_selection_file(LINE / "products" / f"{name}.yaml")).product


def test_paper_product_youbot_stereo_additional_pc_room(line):
    p = product(line, "youbot_stereo_room")
    v = view(p.system)
    assert v["placement"] == {
        "RGBCameraL": "Robot",
        "RGBCameraR": "Robot",
        "StereoVision": "Robot",
        "RobotController": "Robot",
        "TrajectoryFollower": "Robot",
        "RobotDriver": "Robot",
        "MapOptimizer": "Robot",
        "VisualOdometry": "MappingCloud",
        "Database": "MappingCloud",
        "MapMerger": "MappingCloud",
        "StrategyPlanner": "MappingCloud",
    }
    nodes = {n.name: n for c in p.system.containers for n in c.nodes}
    assert (nodes["RobotController"].package, nodes["RobotController"].executable) == (
        "youbot_control",
        "robot_controller",
    )
    assert nodes["TrajectoryFollower"].package == "youbot_control"
    assert nodes["RobotDriver"].package == "youbot_driver"
    assert nodes["StrategyPlanner"].executable == "room_strategy"
    assert (
        nodes["MapOptimizer"].parameters[0].value == "package://stereo_cam/calibration/stereo.yaml"
    )
    # stereo wiring through the new topics
    assert v["bindings"]["RGBCameraL.image"] == "Robot.LeftImg"
    assert v["bindings"]["RGBCameraR.image"] == "Robot.RightImg"
    assert v["bindings"]["StereoVision.left"] == "Robot.LeftImg"
    assert v["bindings"]["StereoVision.right"] == "Robot.RightImg"
    assert v["bindings"]["StereoVision.rgb"] == "Robot.RGBImg"
    assert v["bindings"]["StereoVision.depth"] == "Robot.DepthImg"
    # the migration's rewiring, interface by interface
    assert v["bindings"]["MapOptimizer.keyframes"] == "Robot.Keyframes"
    assert v["bindings"]["MapOptimizer.pose_updated"] == "Robot.PoseUpdated"
    assert v["bindings"]["RobotController.pose_updated"] == "Robot.PoseUpdated"
    assert v["bindings"]["MapOptimizer.add_keyframe"] == "Robot.endpoint.srv_Database_add_keyframe"
    assert v["bindings"]["MapOptimizer.update_poses"] == "Robot.endpoint.srv_Database_update_poses"
    assert v["endpoints"]["Robot"] == sorted(
        [
            "Subscriber:sub_RGBImg",
            "Subscriber:sub_DepthImg",
            "Publisher:pub_Keyframes",
            "Subscriber:sub_PoseUpdated",
            "ServiceServer:srv_Database_add_keyframe",
            "ServiceServer:srv_Database_update_poses",
            "ServiceServer:srv_StrategyPlanner_next_target",
        ]
    )
    assert v["bridges"] == sorted(
        [
            "Robot.endpoint.sub_RGBImg -> MappingCloud.endpoint.pub_RGBImg",
            "Robot.endpoint.sub_DepthImg -> MappingCloud.endpoint.pub_DepthImg",
            "MappingCloud.endpoint.sub_Keyframes -> Robot.endpoint.pub_Keyframes",
            "Robot.endpoint.sub_PoseUpdated -> MappingCloud.endpoint.pub_PoseUpdated",
            "Robot.endpoint.srv_Database_add_keyframe -> "
            "MappingCloud.endpoint.cli_Database_add_keyframe",
            "Robot.endpoint.srv_Database_update_poses -> "
            "MappingCloud.endpoint.cli_Database_update_poses",
            "Robot.endpoint.srv_StrategyPlanner_next_target -> "
            "MappingCloud.endpoint.cli_StrategyPlanner_next_target",
        ]
    )
    sharing = {n.name: n.sharing.name for c in p.system.containers for n in c.nodes}
    assert {n for n, mode in sharing.items() if mode == "protected"} == {
        "Database",
        "MapMerger",
        "StrategyPlanner",
    }
    assert p.system.containers[0].endpoint.robotId == "youbot_07"
    assert not [w for w in p.warnings]


def test_depth_products_keep_everything_in_the_cloud(line):
    p = product(line, "youbot_depth_corridor")
    v = view(p.system)
    assert "DepthCamera" in v["placement"] and "StereoVision" not in v["placement"]
    assert all(v["placement"][n] == "MappingCloud" for n in [*CLOUD_NODES, "MapOptimizer"])
    assert v["bindings"]["DepthCamera.rgb"] == "Robot.RGBImg"
    assert "MappingCloud.endpoint.sub_PoseUpdated -> Robot.endpoint.pub_PoseUpdated" in v["bridges"]
    assert "LeftImg" not in v["topics"]["Robot"] and "Keyframes" not in v["topics"]["Robot"]
    nodes = {n.name: n for c in p.system.containers for n in c.nodes}
    assert nodes["StrategyPlanner"].executable == "corridor_strategy"
    assert nodes["MapOptimizer"].parameters[0].value.endswith("depth.yaml")


def test_roomba_implementations(line):
    nodes = {
        n.name: n for c in product(line, "roomba_depth_room").system.containers for n in c.nodes
    }
    assert nodes["RobotDriver"].package == "create_driver"
    assert nodes["RobotController"].package == "roomba_control"


@pytest.mark.parametrize(
    ("name", "mode"),
    [("roomba_stereo_corridor_private", "private"), ("youbot_depth_room_pc", "public")],
)
def test_sharing_override_from_the_product_selection(line, name, mode):
    p = product(line, name)
    sharing = {n.name: n.sharing.name for c in p.system.containers for n in c.nodes}
    assert {sharing[n] for n in ("Database", "MapMerger", "StrategyPlanner")} == {mode}
    assert sharing["VisualOdometry"] == "private"


def test_every_shipped_product_resolves_without_warnings(line):
    for path in line.product_files():
        resolved = resolve(line, load_selection_file(path)).product
        assert resolved.warnings == (), path.name
