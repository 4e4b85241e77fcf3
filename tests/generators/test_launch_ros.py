"""ROS 1 and ROS 2 launch files of the resolved mapping product (the mapping paper's Fig. 5)."""

from __future__ import annotations

import re

import pytest
import yaml
from lxml import etree

from spl.core.emf import copy_model
from spl.generators.launch.launch_schema import validate_ros1_launch, validate_ros2_launch
from spl.generators.ros1 import launch_files as ros1
from spl.generators.ros2 import launch_files as ros2

from support.launch_system import mapping_product

HOSTILE = "a<b>&c\"d'e $(eval __import__('os').system('true')) \\ $(env HOME) end"


def nodes_of(document: bytes) -> list[etree._Element]:
    return etree.fromstring(document).findall("node")


def by_name(document: bytes, name: str) -> etree._Element:
    (node,) = [n for n in nodes_of(document) if n.get("name") == name]
    return node


def remaps(node: etree._Element) -> dict[str, str]:
    return {r.get("from"): r.get("to") for r in node.findall("remap")}


def ros2_unescape(text: str) -> str:
    # launch.frontend.parse_substitution.replace_escaped_characters
    return re.sub(r"\\(.)", r"\1", text)


def test_one_valid_file_per_container_in_model_order():
    product = mapping_product()
    files1, files2 = ros1.generate(product), ros2.generate(product)
    assert sorted(files1) == ["ros1/MappingCloud.launch", "ros1/Robot.launch"]
    assert sorted(files2) == ["ros2/MappingCloud.launch.xml", "ros2/Robot.launch.xml"]
    for data in files1.values():
        assert validate_ros1_launch(data) == []
        assert data.endswith(b"\n") and data.startswith(b"<?xml")
        data.decode("utf-8")
    for data in files2.values():
        assert validate_ros2_launch(data) == []
    robot = [n.name for n in product.system.containers[0].nodes]
    assert [n.get("name") for n in nodes_of(files1["ros1/Robot.launch"])] == robot
    assert [n.get("name") for n in nodes_of(files2["ros2/Robot.launch.xml"])] == robot
    # endpoint interfaces are run by the cloud engine, not launched
    for data in [*files1.values(), *files2.values()]:
        assert b"endpoint" not in data and b"sub_RGBImg" not in data


def test_ros1_node_attributes_parameters_and_remaps():
    launch = ros1.generate(mapping_product())["ros1/Robot.launch"]
    driver = by_name(launch, "RobotDriver")
    assert dict(driver.attrib) == {
        "pkg": "youbot_driver",
        "type": "youbot_driver_node",
        "name": "RobotDriver",
        "ns": "/youbot",
        "args": "--verbose",
    }
    params = {p.get("name"): (p.get("value"), p.get("type")) for p in driver.findall("param")}
    assert params == {
        "port": ("/dev/ttyUSB0", "str"),
        "rate": ("20.0", "double"),
        "retries": ("3", "int"),
        "simulate": ("false", "bool"),
    }
    (limits,) = driver.findall("rosparam")
    assert limits.get("param") == "limits"
    assert yaml.safe_load(limits.text) == {"max_vel": 0.8, "joints": [1, 2, 3]}
    assert "frame" not in params  # unset: the node's default applies
    assert remaps(driver) == {"cmd_vel": "/cmd_vel"}
    cloud = ros1.generate(mapping_product())["ros1/MappingCloud.launch"]
    assert "ns" not in by_name(cloud, "Database").attrib


def test_remaps_follow_migration_rewiring():
    files = ros1.generate(mapping_product())
    optimizer = by_name(files["ros1/Robot.launch"], "MapOptimizer")
    assert remaps(optimizer) == {
        "keyframes": "/Keyframes",  # topic without a ROS name: /Name
        "pose_updated": "/pose_updated",
        "add_keyframe": "/db/add_keyframe",  # stand-in server carries the real name
        "update_poses": "update_poses",  # stand-in without name: the real server's own name
    }
    controller = by_name(files["ros1/Robot.launch"], "RobotController")
    assert remaps(controller)["next_target"] == "/next_target"
    database = by_name(files["ros1/MappingCloud.launch"], "Database")
    assert remaps(database) == {"add_keyframe": "/db/add_keyframe", "get_map": "/db/get_map"}
    merger = by_name(files["ros1/MappingCloud.launch"], "MapMerger")
    assert remaps(merger) == {"get_map": "/db/get_map"}


def test_ros2_vocabulary():
    launch = ros2.generate(mapping_product())["ros2/Robot.launch.xml"]
    driver = by_name(launch, "RobotDriver")
    assert dict(driver.attrib) == {
        "pkg": "youbot_driver",
        "exec": "youbot_driver_node",
        "name": "RobotDriver",
        "namespace": "/youbot",
        "args": "--verbose",
    }
    params = {p.get("name"): (p.get("value"), p.get("type")) for p in driver.findall("param")}
    assert params["rate"] == ("20.0", "float")
    # ROS 2 has no dict parameters: a yaml mapping becomes nested params
    (limits,) = [p for p in driver.findall("param") if p.get("name") == "limits"]
    assert limits.get("value") is None
    nested = {p.get("name"): (p.get("value"), p.get("type")) for p in limits.findall("param")}
    assert nested == {"max_vel": ("0.8", "yaml"), "joints": ("[1, 2, 3]", "yaml")}
    assert remaps(driver) == {"cmd_vel": "/cmd_vel"}
    ros1_optimizer = by_name(ros1.generate(mapping_product())["ros1/Robot.launch"], "MapOptimizer")
    assert remaps(by_name(launch, "MapOptimizer")) == remaps(ros1_optimizer)


def test_ros2_refuses_yaml_values_ros2_cannot_hold():
    product = mapping_product()
    limits = product.system.containers[0].nodes[5].parameters[4]
    limits.value = "{max_vel: {}}"
    with pytest.raises(ValueError, match=r"RobotDriver\.limits: ROS 2 parameters cannot be null"):
        ros2.generate(product)
    assert validate_ros1_launch(ros1.generate(product)["ros1/Robot.launch"]) == []


def test_deterministic_and_without_timestamps():
    product = mapping_product()
    first = {**ros1.generate(product), **ros2.generate(product)}
    product.system = copy_model(product.system)
    second = {**ros1.generate(product), **ros2.generate(product)}
    assert first == second
    for data in first.values():
        assert not re.search(rb"20\d\d-\d\d-\d\d|\d\d:\d\d:\d\d", data)
        assert b"youbot_stereo_room" in data  # provenance header names the product


def test_hostile_string_is_escaped_and_never_substituted():
    product = mapping_product(string_value=HOSTILE)
    launch1 = ros1.generate(product)["ros1/Robot.launch"]
    launch2 = ros2.generate(product)["ros2/Robot.launch.xml"]
    assert validate_ros1_launch(launch1) == [] and validate_ros2_launch(launch2) == []
    # ROS 1: no escape for '$' exists, so the value travels as non-substituted YAML text
    optimizer = by_name(launch1, "MapOptimizer")
    assert optimizer.find("param") is None
    (rosparam,) = optimizer.findall("rosparam")
    assert rosparam.get("param") == "CameraInfo" and rosparam.get("subst_value") is None
    assert yaml.safe_load(rosparam.text) == HOSTILE
    assert b"<b>" not in launch1 and b"&lt;b&gt;" in launch1
    # ROS 2: backslash escapes, read back by the frontend's own unescaping
    value = by_name(launch2, "MapOptimizer").find("param").get("value")
    assert ros2_unescape(value) == HOSTILE
    assert re.search(r"(?<!\\)\$", value) is None


@pytest.mark.parametrize("text", ["  padded\t", "line\nbreak ", ""])
def test_ros1_strings_roslaunch_would_strip(text):
    launch = ros1.generate(mapping_product(string_value=text))["ros1/Robot.launch"]
    assert validate_ros1_launch(launch) == []
    optimizer = by_name(launch, "MapOptimizer")
    if text == text.strip():
        assert optimizer.find("param").get("value") == text
    else:
        assert yaml.safe_load(optimizer.find("rosparam").text) == text
    value = (
        by_name(
            ros2.generate(mapping_product(string_value=text))["ros2/Robot.launch.xml"],
            "MapOptimizer",
        )
        .find("param")
        .get("value")
    )
    assert ros2_unescape(value) == text


def test_plain_markup_characters_round_trip_in_a_ros1_param():
    text = '<tag attr="x">&amp;\'</tag>'
    optimizer = by_name(
        ros1.generate(mapping_product(string_value=text))["ros1/Robot.launch"], "MapOptimizer"
    )
    assert optimizer.find("param").get("value") == text


def test_refuses_what_roslaunch_would_misread():
    product = mapping_product()
    driver = product.system.containers[0].nodes[5]
    driver.args = "--port $(env PORT)"
    with pytest.raises(ValueError, match="substitute"):
        ros1.generate(product)
    assert "\\$(env PORT)" in ros2.generate(product)["ros2/Robot.launch.xml"].decode()
    driver.args = None
    driver.parameters[2].value = "three"
    with pytest.raises(ValueError, match=r"retries.*not a valid int"):
        ros1.generate(product)
    driver.parameters[2].value = "3"
    driver.parameters[3].value = "yes"
    with pytest.raises(ValueError, match="simulate"):
        ros2.generate(product)


def test_node_without_implementation_is_an_error():
    product = mapping_product()
    product.system.containers[1].nodes[0].package = None
    with pytest.raises(ValueError, match=r"MappingCloud\.VisualOdometry has no implementation"):
        ros1.generate(product)
    with pytest.raises(ValueError, match="no implementation"):
        ros2.generate(product)
