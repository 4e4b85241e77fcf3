"""What each output makes of an action (docs/deployment.md, "Actions"), on the
navigation test line: ROS 1 remaps the five actionlib topics under the action's name,
read back by roslaunch's own loader; ROS 2 remaps the action's one name; Zenoh lists it
in action_clients where goals are sent and action_servers where they are served;
Rapyuta carries the five topics across the bridge, goal and cancel towards the server,
status, feedback and result back. (``spl smoke`` rehearses them with actionlib:
tests/cli/test_smoke_action_plan.py, tests/live/test_smoke_actions.py.)"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import json5
import pytest
from lxml import etree

from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle
from spl.generators.launch.launch_schema import validate_ros1_launch, validate_ros2_launch
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list
from spl.smoke.processes import find_ros

NAVIGATION = Path(__file__).parents[1] / "models" / "navigation"
PARTS = ("goal", "cancel", "status", "feedback", "result")
LOADER = """
import json, sys
import roslaunch.config, roslaunch.xmlloader
config = roslaunch.config.ROSLaunchConfig()
roslaunch.xmlloader.XmlLoader().load(sys.argv[1], config, verbose=False)
print(json.dumps({node.name: node.remap_args for node in config.nodes}))
"""


def bundle(*features: str) -> dict[str, bytes]:
    line = load_product_line(NAVIGATION)
    selection = selection_from_list(",".join(["Navigation", *features]))
    product = resolve(line, selection).product
    return build_bundle(product, BundleOptions(render_diagrams=False)).files


@pytest.fixture(scope="module")
def across() -> dict[str, bytes]:
    return bundle("Planning")


@pytest.fixture(scope="module")
def on_board() -> dict[str, bytes]:
    return bundle("Planning", "OnBoardPlanning")


def roslaunch_remaps(tmp_path: Path, launch: bytes) -> dict[str, list[list[str]]]:
    """The remaps of every node as roslaunch's own XML loader reads the file."""
    path = tmp_path / "container.launch"
    path.write_bytes(launch)
    loaded = subprocess.run(
        [find_ros().python, "-I", "-c", LOADER, str(path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert loaded.returncode == 0, loaded.stderr
    return json.loads(loaded.stdout)


def test_ros1_remaps_the_five_actionlib_topics_of_each_end(tmp_path, across, on_board) -> None:
    assert validate_ros1_launch(across["ros1/Robot.launch"]) == []
    robot = roslaunch_remaps(tmp_path, across["ros1/Robot.launch"])
    cloud = roslaunch_remaps(tmp_path, across["ros1/Cloud.launch"])
    assert robot["Behaviour"] == [[f"navigate/{p}", f"/move_base/{p}"] for p in PARTS]
    assert cloud["Planner"][2:] == [[f"move_base/{p}", f"/move_base/{p}"] for p in PARTS]
    assert cloud["Planner"][:2] == [["scan", "/scan"], ["cmd_vel", "/cmd_vel"]]
    # after the migration both ends are on the robot, under the same five names
    moved = roslaunch_remaps(tmp_path, on_board["ros1/Robot.launch"])
    assert moved["Behaviour"] == robot["Behaviour"]
    assert moved["Planner"][2:] == cloud["Planner"][2:]
    assert "ros1/Cloud.launch" not in on_board


def remaps2(launch: bytes) -> dict[str, list[tuple[str, str]]]:
    root = etree.fromstring(launch)
    return {
        node.get("name"): [(r.get("from"), r.get("to")) for r in node.iter("remap")]
        for node in root.iter("node")
    }


def test_ros2_remaps_the_action_by_its_one_name(across) -> None:
    assert validate_ros2_launch(across["ros2/Robot.launch.xml"]) == []
    assert remaps2(across["ros2/Robot.launch.xml"])["Behaviour"] == [("navigate", "/move_base")]
    assert remaps2(across["ros2/Cloud.launch.xml"])["Planner"][-1] == ("move_base", "/move_base")


def test_zenoh_lists_the_action_where_goals_are_sent_and_served(across, on_board) -> None:
    robot = json5.loads(across["zenoh/rover_1.json5"].decode())["plugins"]["ros2dds"]["allow"]
    cloud = json5.loads(across["zenoh/Cloud_rover_1.json5"].decode())["plugins"]["ros2dds"]
    assert (robot["action_clients"], robot["action_servers"]) == (["/move_base"], [])
    allow = cloud["allow"]
    assert (allow["action_clients"], allow["action_servers"]) == ([], ["/move_base"])
    # on the robot nothing of the action crosses: no bridge lists it
    for path, data in on_board.items():
        if path.endswith(".json5") and "rover" in path:
            allowed = json5.loads(data.decode())["plugins"]["ros2dds"]["allow"]
            assert allowed["action_clients"] == allowed["action_servers"] == []


def test_rapyuta_carries_the_five_topics_in_their_directions(across) -> None:
    config = json.loads(across["rapyuta/Robot.json"])
    by_tag = {(i["eTag"], i["iTag"]): i for i in config["interfaces"]}
    connections = {(c["tagA"], c["tagB"]) for c in config["connections"]}
    for part in PARTS:
        tag = f"Planner_move_base_{part}"
        towards_server = part in ("goal", "cancel")
        robot, cloud = ("rover_1", "Cloud_rover_1")
        enters, delivers = (robot, cloud) if towards_server else (cloud, robot)
        assert (f"{enters}/sub_{tag}", f"{delivers}/pub_{tag}") in connections, part
        for place, way in ((enters, "sub"), (delivers, "pub")):
            entry = by_tag[(place, f"{way}_{tag}")]
            assert entry["addr"] == f"/move_base/{part}"
            role = "Subscriber" if way == "sub" else "Publisher"
            suffix = "Converter" if place == robot else "Interface"
            assert entry["iType"] == role + suffix
    classes = {by_tag[("rover_1", f"pub_Planner_move_base_{p}")]["iCls"] for p in PARTS[2:]}
    assert classes == {
        "actionlib_msgs/GoalStatusArray",
        "move_base_msgs/MoveBaseActionFeedback",
        "move_base_msgs/MoveBaseActionResult",
    }
    goal = by_tag[("rover_1", "sub_Planner_move_base_goal")]["iCls"]
    cancel = by_tag[("rover_1", "sub_Planner_move_base_cancel")]["iCls"]
    assert (goal, cancel) == ("move_base_msgs/MoveBaseActionGoal", "actionlib_msgs/GoalID")


def test_the_diagram_legend_shows_action_kinds_where_the_product_has_an_action(
    across,
) -> None:
    legend = next(
        line for line in across["architecture.dot"].decode().splitlines() if "legend [" in line
    )
    assert ">action server<" in legend and ">action client<" in legend
    mapping = load_product_line(NAVIGATION.parents[2] / "product_lines" / "mapping3d")
    selection = selection_from_list("YouBot,Stereo,AdditionalPC,Room")
    files = build_bundle(
        resolve(mapping, selection).product, BundleOptions(render_diagrams=False)
    ).files
    legend = next(
        line for line in files["architecture.dot"].decode().splitlines() if "legend [" in line
    )
    assert ">service client<" in legend and "action" not in legend
