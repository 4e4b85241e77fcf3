"""What a smoke rehearsal expects of an action (docs/smoke.md, "Actions"), read from a
bundle of the shipped navigation line, and how the live graph is held to it (no ROS
started here; tests/live/test_smoke_actions.py runs it with the real actionlib).

The mission's client expects a result and feedback from the cloud planner behind the
endpoint's stand-in; the stand-ins get the action's five topics with their directions
and message types; the master must list each of the five on the right side, and a
client counts only when both the result and the feedback came from its server.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from spl.smoke.live import LiveGraph, Row, compare
from spl.smoke.planning import actions_of, load_plan
from spl.smoke.processes import actionlib_missing, find_ros

from support.smoke_runs import ROOT, write_product

NAVIGATION = ROOT / "product_lines" / "navigation"
PARTS = ("goal", "cancel", "status", "feedback", "result")
CLIENT_SENDS = ("goal", "cancel")  # actionlib's client publishes these, its server the rest
PLANNER = "NavCloud.Planner.move_base"


@pytest.fixture(scope="module")
def across(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("across") / "bundle"
    return write_product(NAVIGATION, NAVIGATION / "products" / "cloud_static_map.yaml", out)


def by_id(plan) -> dict:
    return {i.id: i for i in plan.interfaces()}


def test_the_client_expects_the_cloud_planner_behind_the_endpoint(across) -> None:
    found = by_id(load_plan(across))
    navigate = found["Rover.Mission.navigate"]
    assert (navigate.server, navigate.ros_name, navigate.type) == (
        PLANNER,
        "/move_base",
        "move_base_msgs/MoveBase",
    )
    stand_in = found["Rover.endpoint.asrv_Planner_move_base"]
    assert stand_in.forward == ("NavCloud", "acli_Planner_move_base")
    # the answers come back to the robot's stand-in, which the client waits on
    relay = found["NavCloud.endpoint.acli_Planner_move_base"]
    assert relay.peers == (("Rover", "asrv_Planner_move_base"),)
    assert relay.required and relay.server == PLANNER


def test_the_stand_ins_get_the_five_topics_with_directions_and_types(across, tmp_path) -> None:
    description = load_plan(across).stand_in_description(tmp_path)
    mission = description["containers"]["Rover"]["nodes"]["/Mission"]
    (navigate,) = [i for i in mission["interfaces"] if i["name"] == "navigate"]
    assert navigate["kind"] == "action_client"
    assert [(p["suffix"], p["from_consumer"], p["type"]) for p in navigate["parts"]] == [
        ("goal", True, "move_base_msgs/MoveBaseActionGoal"),
        ("cancel", True, "actionlib_msgs/GoalID"),
        ("status", False, "actionlib_msgs/GoalStatusArray"),
        ("feedback", False, "move_base_msgs/MoveBaseActionFeedback"),
        ("result", False, "move_base_msgs/MoveBaseActionResult"),
    ]
    lidar = description["containers"]["Rover"]["nodes"]["/Lidar"]
    assert lidar["interfaces"][0]["parts"] == []  # a topic is its name alone


def live_graph(plan, leave_out: tuple[str, str] | None = None) -> LiveGraph:
    """The graph a correct rehearsal shows the Rover's master: every interface where
    the plan binds it, an action as its five topics (``leave_out``: one (node, topic)
    registration missing)."""
    graph = LiveGraph()
    rover = next(c for c in plan.containers if c.name == "Rover")
    for node in rover.nodes:
        for interface in node.interfaces:
            if interface.kind.family.ros1_topics:
                for part in PARTS:
                    topic = f"{interface.ros_name}/{part}"
                    if (node.ros_name, topic) == leave_out:
                        continue
                    sends = (part in CLIENT_SENDS) != interface.kind.provides
                    side = graph.publishers if sends else graph.subscribers
                    side.setdefault(topic, set()).add(node.ros_name)
            elif interface.kind.publishes:
                graph.publishers.setdefault(interface.ros_name, set()).add(node.ros_name)
                graph.types[interface.ros_name] = interface.type
            elif interface.kind.subscribes:
                graph.subscribers.setdefault(interface.ros_name, set()).add(node.ros_name)
    graph.types |= {
        "/move_base/goal": "move_base_msgs/MoveBaseActionGoal",
        "/move_base/cancel": "actionlib_msgs/GoalID",
        "/move_base/status": "actionlib_msgs/GoalStatusArray",
        "/move_base/feedback": "move_base_msgs/MoveBaseActionFeedback",
        "/move_base/result": "move_base_msgs/MoveBaseActionResult",
    }
    return graph


def statuses(plan, result: int = 2, feedback: int = 2) -> dict:
    """Status files of the Rover's stand-ins: the mission's client answered ``result``
    times and fed ``feedback`` times by the planner; every subscriber fed."""
    rover = next(c for c in plan.containers if c.name == "Rover")
    found = {}
    for node in rover.nodes:
        entries = {}
        for interface in node.interfaces:
            entries[interface.name] = {
                "resolved": interface.ros_name,
                "received": {s: 2 for s in interface.sources},
                "answered_by": {PLANNER: result} if result else {},
                "feedback_from": {PLANNER: feedback} if feedback else {},
                "sent": 3,
                "served": 2,
            }
        found[node.ros_name] = {"ready": True, "interfaces": entries}
    return found


def rover_rows(plan, graph: LiveGraph, status: dict) -> dict[str, Row]:
    rover = next(c for c in plan.containers if c.name == "Rover")
    params = {p.ros_name: (True, p.value) for node in rover.nodes for p in node.parameters}
    rows = compare(rover, graph, status, params)
    return {f"{r.node}.{r.interface}@{r.topic}": r for r in rows}


def test_a_client_answered_with_result_and_feedback_passes(across) -> None:
    plan = load_plan(across)
    rows = rover_rows(plan, live_graph(plan), statuses(plan))
    navigate = rows["Mission.navigate@/move_base"]
    assert navigate.ok, navigate
    assert navigate.expected == f"result and feedback from {PLANNER}"
    assert navigate.seen == f"result from {PLANNER} (2), feedback from {PLANNER} (2)"
    assert rows["endpoint.asrv_Planner_move_base@/move_base"].seen == (
        "provides action (2 goals answered)"
    )
    # the five topics are the model's: none of them is reported as unmodelled
    assert all(row.ok for row in rows.values()), [r for r in rows.values() if not r.ok]


@pytest.mark.parametrize(("result", "feedback"), [(0, 2), (2, 0)], ids=["no result", "no feedback"])
def test_a_client_without_result_or_feedback_fails(across, result, feedback) -> None:
    plan = load_plan(across)
    rows = rover_rows(plan, live_graph(plan), statuses(plan, result, feedback))
    assert not rows["Mission.navigate@/move_base"].ok


def test_each_of_the_five_topics_must_be_registered_on_its_side(across) -> None:
    plan = load_plan(across)
    missing = ("/Mission", "/move_base/result")
    rows = rover_rows(plan, live_graph(plan, leave_out=missing), statuses(plan))
    navigate = rows["Mission.navigate@/move_base"]
    assert not navigate.ok and "not registered on /move_base/result" in navigate.seen
    # subscribing where the model does not put it is a row of its own
    graph = live_graph(plan)
    graph.subscribers["/move_base/results"] = {"/Mission"}
    stray = rover_rows(plan, graph, statuses(plan))["Mission.?@/move_base/results"]
    assert not stray.ok and stray.expected == "not in the model"


def test_an_unexpected_topic_of_an_action_is_named_by_its_action(across) -> None:
    plan = load_plan(across)
    graph = live_graph(plan)
    # the mission's client takes goals as a server would: its row names its action
    graph.subscribers["/move_base/goal"].add("/Mission")
    # and the lidar, which has no action, publishes the planner's feedback
    graph.publishers["/move_base/feedback"].add("/Lidar")
    rows = rover_rows(plan, graph, statuses(plan))
    stray = rows["Mission.navigate@/move_base/goal"]
    assert not stray.ok and stray.expected == "not in the model"
    assert stray.seen == "subscribes move_base_msgs/MoveBaseActionGoal"
    lidar = rows["Lidar.action /move_base@/move_base/feedback"]
    assert not lidar.ok and lidar.expected == "not in the model"
    assert not [r for r in rows.values() if "?" in r.interface]


def test_a_wrong_message_type_on_one_of_the_topics_fails(across) -> None:
    plan = load_plan(across)
    graph = live_graph(plan)
    graph.types["/move_base/feedback"] = "move_base_msgs/MoveBaseFeedback"
    navigate = rover_rows(plan, graph, statuses(plan))["Mission.navigate@/move_base"]
    assert not navigate.ok
    assert "/move_base/feedback type move_base_msgs/MoveBaseFeedback" in navigate.seen


def test_without_actionlib_the_actions_are_left_out_and_named(across) -> None:
    plan = load_plan(across, actions=False)
    assert not [i for i in plan.interfaces() if i.kind.family.ros1_topics]
    assert "Rover.Lidar.scan" in by_id(plan)  # the rest is rehearsed as before
    from spl.pipeline import read_bundle

    system, _ = read_bundle(across)
    assert actions_of(system) == [
        "action client Rover.Mission.navigate",
        "action server NavCloud.Planner.move_base",
    ]


def test_actionlib_is_looked_for_in_the_python_that_runs_the_stand_ins() -> None:
    # spl's own virtual environment has no actionlib (nor rospy): said in one line
    assert actionlib_missing(sys.executable) == (
        f"actionlib not importable by {sys.executable}: apt-get install python3-actionlib"
    )
    assert actionlib_missing(find_ros().python) is None  # Debian's python3-actionlib
