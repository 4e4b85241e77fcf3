"""The shipped orchard line against architectures worked out by hand from
orchard.tsm, orchard.fm and orchard.rm (not from spl's output): where every node
runs, the ROS 1 remaps of the nodes the resolution model touches, and the bridges."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from lxml import etree

from spl.generators.ros1 import launch_files as ros1
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file

LINE = Path(__file__).resolve().parents[2] / "product_lines" / "orchard"
HARVESTER = {"Camera", "Driver", "Navigator", "ArmController", "Gripper"}


@pytest.fixture(scope="module")
def line():
    return load_product_line(LINE)


def product(line, name: str):
    return resolve(line, load_selection_file(LINE / "products" / f"{name}.yaml")).product


def placement(system: Any) -> dict[str, set[str]]:
    """Node names per container (both robots have a Camera and a Driver)."""
    return {c.name: {n.name for n in c.nodes} for c in system.containers}


def bridges(system: Any) -> set[str]:
    """A topic bridge as its two topics, a service bridge as the client's container
    and the real server behind it."""
    found = set()
    for connection in system.connections:
        source, target = connection.source, connection.target
        side = source.eContainer().eContainer().name
        if source.eClass.name == "ServiceServer":
            server = target.server
            found.add(
                f"{side} -> {server.eContainer().eContainer().name}."
                f"{server.eContainer().name}.{server.name}"
            )
        else:
            other = target.eContainer().eContainer().name
            found.add(f"{side}.{source.topic.name} -> {other}.{target.topic.name}")
    return found


def launch_remaps(launch: dict[str, bytes], container: str, node: str) -> dict[str, str]:
    (element,) = [
        n
        for n in etree.fromstring(launch[f"ros1/{container}.launch"]).iter("node")
        if n.get("name") == node
    ]
    return {r.get("from"): r.get("to") for r in element.iter("remap")}


def launch_params(launch: dict[str, bytes], container: str, node: str) -> dict[str, str]:
    (element,) = [
        n
        for n in etree.fromstring(launch[f"ros1/{container}.launch"]).iter("node")
        if n.get("name") == node
    ]
    return {p.get("name"): p.get("value") for p in element.iter("param")}


def test_scout_with_public_yield_map(line):
    """Cloud detection and planning, soft gripper, scout at 4 m, yield map public."""
    p = product(line, "scout_yield_public")
    assert placement(p.system) == {
        "Harvester": HARVESTER,
        "Scout": {"Camera", "Driver", "Mission"},
        "OrchardCloud": {"FruitDetector", "PathPlanner", "YieldMapper", "RowScheduler"},
    }
    # the template's three bridges, the scout's new topic bridged to the cloud in the
    # element that creates it, and the scout's service bridge to the row scheduler
    assert bridges(p.system) == {
        "Harvester.Image -> OrchardCloud.HarvesterImage",
        "OrchardCloud.Fruits -> Harvester.Fruits",
        "Harvester -> OrchardCloud.PathPlanner.plan",
        "Scout.RowImages -> OrchardCloud.ScoutImage",
        "Scout -> OrchardCloud.RowScheduler.next_row",
    }
    launch = ros1.generate(p)
    assert launch_remaps(launch, "Scout", "Camera") == {"image": "/camera/image_raw"}
    assert launch_remaps(launch, "Scout", "Mission") == {
        "odom": "/mavros/local_position/odom",
        "next_row": "/scout/next_row",
    }
    assert launch_remaps(launch, "OrchardCloud", "YieldMapper") == {
        "image": "/scout/camera/image_raw",
        "yield_map": "/orchard/yield_map",
    }
    assert launch_remaps(launch, "OrchardCloud", "PathPlanner") == {
        "plan": "/planner/make_plan",
        "yield_map": "/orchard/yield_map",
    }
    assert launch_remaps(launch, "Harvester", "ArmController") == {
        "targets": "/fruit/detections",
        "grasp": "/gripper/grasp",
    }
    assert launch_params(launch, "Scout", "Mission") == {"altitude": "4.0"}
    assert launch_params(launch, "OrchardCloud", "YieldMapper") == {"resolution": "0.25"}
    assert launch_params(launch, "OrchardCloud", "FruitDetector")["threshold"] == "0.5"
    assert launch_params(launch, "OrchardCloud", "PathPlanner") == {"use_yield_map": "true"}
    assert launch_params(launch, "Harvester", "Navigator")["plan_timeout"] == "5.0"
    nodes = {(c.name, n.name): n for c in p.system.containers for n in c.nodes}
    assert nodes["Harvester", "Gripper"].executable == "soft_gripper"
    # the product overrides YieldMapping's protected sharing mode
    assert {k for k, n in nodes.items() if n.sharing.name != "private"} == {
        ("OrchardCloud", "YieldMapper")
    }
    assert nodes["OrchardCloud", "YieldMapper"].sharing.name == "public"
    assert not p.warnings


def test_everything_on_board(line):
    """Detector and planner migrate to the harvester: the detector reads the camera
    there and feeds the arm through the new topic, the navigator's plan service is
    served locally, nothing crosses to the cloud and the empty cloud is gone."""
    p = product(line, "onboard_soft")
    # (an unused robot container is kept empty; only empty cloud containers go)
    assert {c: nodes for c, nodes in placement(p.system).items() if nodes} == {
        "Harvester": HARVESTER | {"FruitDetector", "PathPlanner"},
    }
    assert bridges(p.system) == set()
    harvester = next(c for c in p.system.containers if c.name == "Harvester")
    nodes = {n.name: n for n in harvester.nodes}
    (plan,) = [i for i in nodes["Navigator"].interfaces if i.name == "plan"]
    assert plan.server.eContainer() is nodes["PathPlanner"]
    launch = ros1.generate(p)
    assert launch_remaps(launch, "Harvester", "FruitDetector") == {
        "image": "/camera/image_raw",
        "detections": "/fruit/detections_onboard",
    }
    assert launch_remaps(launch, "Harvester", "ArmController") == {
        "targets": "/fruit/detections_onboard",
        "grasp": "/gripper/grasp",
    }
    assert launch_remaps(launch, "Harvester", "Navigator") == {
        "odom": "/odom",
        "cmd_vel": "/cmd_vel",
        "plan": "/planner/make_plan",
    }
    # the yield map is off: the planner's subscription stays unconnected
    assert launch_remaps(launch, "Harvester", "PathPlanner") == {"plan": "/planner/make_plan"}
    assert launch_params(launch, "Harvester", "PathPlanner") == {"use_yield_map": "false"}
    assert launch_params(launch, "Harvester", "FruitDetector") == {
        "threshold": "0.7",
        "model": "yolo_apple_int8.onnx",
    }
    assert launch_params(launch, "Harvester", "Navigator")["plan_timeout"] == "1.0"
    assert nodes["Gripper"].executable == "soft_gripper"


def test_reports_keep_both_robots_nodes_of_one_name(line):
    # both robots declare Camera and Driver: the manifest and the removed-node summary
    # name them by container instead of folding two nodes into one entry (it read
    # "Camera": "Scout" and listed no removed Camera before)
    import json

    from spl.generators.bundle.writer import bundle_files

    scouting = product(line, "scout_yield_public")
    manifest = json.loads(bundle_files(scouting)["manifest.json"])
    assert manifest["placement"]["Harvester.Camera"] == "Harvester"
    assert manifest["placement"]["Scout.Camera"] == "Scout"
    assert manifest["placement"]["Navigator"] == "Harvester"
    assert "Camera" not in manifest["placement"] and "Camera" not in manifest["sharing"]
    alone = resolve(line, load_selection_file(LINE / "products" / "onboard_soft.yaml"))
    assert {"Scout.Camera", "Scout.Driver"} <= set(alone.removed_nodes)
    assert "Harvester.Camera" not in alone.removed_nodes
