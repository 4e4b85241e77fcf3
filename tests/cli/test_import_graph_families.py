"""``spl import graph`` looks for the interfaces of a family made of several ROS 1
topics (an action's five) only in the families made of topics alone
(docs/architecture.md, "Interface kinds"): the ROS 1 master lists no service among a
group's topics, so a family with a service among its parts (dynamic_reconfigure's
``set_parameters``, ``PartTopic.carrier``) is not read as a group of topics, and its
topics (every ``move_base`` publishes ``parameter_descriptions`` and
``parameter_updates``) stay topics without a note."""

from __future__ import annotations

from spl.importers.graph.actions import find_actions
from spl.metamodels.interface_kinds import FAMILIES, SERVICE, Family, PartTopic

RECONFIGURE = Family(
    "reconfigure",
    False,
    ("reconfigures", "reconfigured by"),
    ("service_clients", "service_servers"),
    "reconfigure server",
    (
        PartTopic("set_parameters", True, "dynamic_reconfigure/Reconfigure", SERVICE),
        PartTopic("parameter_descriptions", False, "dynamic_reconfigure/ConfigDescription"),
        PartTopic("parameter_updates", False, "dynamic_reconfigure/Config"),
    ),
)


def test_a_family_with_a_service_part_is_not_read_from_topics() -> None:
    action = {f"/move_base/{p}" for p in ("goal", "cancel", "status", "feedback", "result")}
    reconfigure = {"/move_base/parameter_descriptions", "/move_base/parameter_updates"}
    publishes = {"/move_base": set(reconfigure), "/mission": set()}
    subscribes: dict[str, set[str]] = {"/move_base": set(), "/mission": set()}
    for topic in sorted(action):
        to_server = topic.endswith(("goal", "cancel"))
        (subscribes if to_server else publishes)["/move_base"].add(topic)
        (publishes if to_server else subscribes)["/mission"].add(topic)
    types = {
        "/move_base/goal": "move_base_msgs/MoveBaseActionGoal",
        "/move_base/cancel": "actionlib_msgs/GoalID",
        "/move_base/status": "actionlib_msgs/GoalStatusArray",
        "/move_base/feedback": "move_base_msgs/MoveBaseActionFeedback",
        "/move_base/result": "move_base_msgs/MoveBaseActionResult",
        "/move_base/parameter_descriptions": "dynamic_reconfigure/ConfigDescription",
        "/move_base/parameter_updates": "dynamic_reconfigure/Config",
    }
    found, notes = find_actions(publishes, subscribes, types, (*FAMILIES, RECONFIGURE))
    assert (found, notes) == find_actions(publishes, subscribes, types)
    assert [(a.name, a.type, a.server, a.clients) for a in found] == [
        ("/move_base", "move_base_msgs/MoveBase", "/move_base", ("/mission",))
    ]
    assert notes == []
