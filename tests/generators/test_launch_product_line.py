"""Launch files and diagrams of products derived from .tsm/.fm/.rm text (tests/models/launch)."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from lxml import etree

from spl.dsl.fm.printer import format_formula
from spl.generators.diagrams import (
    architecture as diagrams,
    feature_model as feature_model_diagram,
    graphviz_output,
)
from spl.generators.launch.launch_schema import validate_ros1_launch, validate_ros2_launch
from spl.generators.ros1 import launch_files as ros1
from spl.generators.ros2 import launch_files as ros2
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

FLEET = Path(__file__).parents[1] / "models" / "launch"
FRAME_ID = 'laser <front> & "top" $(env HOME)'


@pytest.fixture(scope="module")
def line():
    return load_product_line(FLEET)


def product(line, features: str):
    return resolve(line, selection_from_list(features)).product


def node(document: bytes, name: str) -> etree._Element:
    (found,) = [n for n in etree.fromstring(document).iter("node") if n.get("name") == name]
    return found


def remaps(element: etree._Element) -> dict[str, str]:
    return {r.get("from"): r.get("to") for r in element.iter("remap")}


@pytest.mark.parametrize("features", ["Fleet", "CloudMapping", "CloudMapping,OnboardSlam"])
def test_every_product_gives_valid_launch_files(line, features):
    derived = product(line, features)
    files1, files2 = ros1.generate(derived), ros2.generate(derived)
    containers = [c.name for c in derived.system.containers]
    assert sorted(files1) == sorted(f"ros1/{c}.launch" for c in containers)
    assert sorted(files2) == sorted(f"ros2/{c}.launch.xml" for c in containers)
    for data in files1.values():
        assert validate_ros1_launch(data) == [], data.decode()
    for data in files2.values():
        assert validate_ros2_launch(data) == [], data.decode()
    launched = {n.get("name") for d in files1.values() for n in etree.fromstring(d).iter("node")}
    assert launched == {n.name for c in derived.system.containers for n in c.nodes}


def test_parameters_from_text_keep_type_and_value(line):
    derived = product(line, "Fleet")
    lidar1 = node(ros1.generate(derived)["ros1/Scout.launch"], "Lidar")
    assert lidar1.get("ns") == "/scout" and lidar1.get("args") == "--serial /dev/ttyACM0"
    params = {p.get("name"): (p.get("value"), p.get("type")) for p in lidar1.iter("param")}
    assert params == {
        "angle_min": ("-2.2", "double"),
        "skip": ("0", "int"),
        "intensity": ("true", "bool"),
    }
    rosparams = {r.get("param"): yaml.safe_load(r.text) for r in lidar1.iter("rosparam")}
    assert rosparams == {
        "frame_id": FRAME_ID,
        "filters": {"median": {"window": 5}, "range": [0.1, 30.0]},
    }
    lidar2 = node(ros2.generate(derived)["ros2/Scout.launch.xml"], "Lidar")
    typed = {p.get("name"): p.get("type") for p in lidar2.findall("param")}
    assert typed == {
        "frame_id": "str",
        "angle_min": "float",
        "skip": "int",
        "intensity": "bool",
        "filters": None,  # a mapping: nested params, as in a ROS 2 parameter file
    }
    leaves = {
        ".".join(a.get("name") for a in reversed([p, *p.iterancestors("param")])): p.get("value")
        for p in lidar2.iter("param")
        if p.get("value") is not None and p.get("type") == "yaml"
    }
    assert leaves == {"filters.median.window": "5", "filters.range": "[0.1, 30.0]"}
    assert lidar2.get("namespace") == "/scout"


def test_migrated_server_is_reached_through_the_endpoints(line):
    cloud_only = product(line, "CloudMapping")
    migrated = product(line, "CloudMapping,OnboardSlam")
    before = ros1.generate(cloud_only)
    after = ros1.generate(migrated)
    assert "Slam" in {n.get("name") for n in etree.fromstring(before["ros1/Mapping.launch"])}
    assert remaps(node(after["ros1/Scout.launch"], "Slam")) == remaps(
        node(before["ros1/Mapping.launch"], "Slam")
    )
    # MapSaver stays in the cloud and calls the stand-in under the real server's name
    assert remaps(node(after["ros1/Mapping.launch"], "MapSaver")) == remaps(
        node(before["ros1/Mapping.launch"], "MapSaver")
    )
    navigator = remaps(node(after["ros1/Scout.launch"], "Navigator"))
    assert navigator["plan"] == navigator["make_plan"] == "/scout/make_plan"


def test_architecture_diagram_of_a_migrated_product(line):
    migrated = product(line, "CloudMapping,OnboardSlam")
    svg = diagrams.generate(migrated)["architecture.svg"]
    root = etree.fromstring(svg)
    shown = {t.text for t in root.iter("{*}text")}
    assert {"Lidar", "Navigator", "Slam", "MapSaver", "Scan", "MapView", "Cmd"} <= shown
    assert {"migrated from Mapping", "«protected»", "group mappers"} <= shown
    assert diagrams.generate(product(line, "CloudMapping,OnboardSlam"))["architecture.svg"] == svg


def test_feature_model_diagram_from_text(line):
    graph = feature_model_diagram.feature_model_graph(
        line.fm, {"Fleet", "CloudMapping"}, formula_text=format_formula
    )
    root = etree.fromstring(graphviz_output.render_bytes(graph, "svg"))
    shown = {t.text for t in root.iter("{*}text")}
    assert {"Fleet", "CloudMapping", "OnboardSlam", "OnboardSlam requires CloudMapping"} <= shown
