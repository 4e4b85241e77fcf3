"""``spl smoke`` holds each ROS 1 part of an interface to what its carrier is on the
master (``PartTopic.carrier``, docs/architecture.md "Interface kinds"): a topic part
published or subscribed with its type, as actionlib's five are, and a part that is a
service (dynamic_reconfigure's ``set_parameters``) registered by the server and called
by the client, with no topic type to compare (the master lists none for a service); and
says a family's calls and answers in the family's words (``Family.answers``), so that a
family with such a part is checked without an edit of the comparison."""

from __future__ import annotations

from dataclasses import replace

from spl.metamodels.interface_kinds import ACTION, SERVICE, TOPIC, Answers, PartTopic, side
from spl.smoke.live import LiveGraph, compare, registrations
from spl.smoke.plan import ContainerPlan, Interface, NodePlan

RECONFIGURE = replace(
    ACTION,
    name="reconfigure",
    ros1_topics=(
        PartTopic("set_parameters", True, "dynamic_reconfigure/Reconfigure", SERVICE),
        PartTopic("parameter_updates", False, "dynamic_reconfigure/Config"),
    ),
    needs_actionlib=False,
    answers=Answers("reconfiguration", "answer and updates", "answered by", "updates"),
)
SERVER = replace(side(ACTION, True), family=RECONFIGURE)
CLIENT = replace(side(ACTION, False), family=RECONFIGURE)
TYPE = "move_base/MoveBaseConfig"


def planned(kind, node: str, name: str) -> Interface:
    return Interface("Cloud", node, name, kind, TYPE, "/move_base")


def test_each_part_is_registered_as_its_carrier_says() -> None:
    assert registrations(planned(SERVER, "Planner", "params")) == [
        (side(SERVICE, True), "/move_base/set_parameters", "dynamic_reconfigure/Reconfigure"),
        (side(TOPIC, True), "/move_base/parameter_updates", "dynamic_reconfigure/Config"),
    ]
    assert registrations(planned(CLIENT, "Tuner", "planner")) == [
        (side(SERVICE, False), "/move_base/set_parameters", "dynamic_reconfigure/Reconfigure"),
        (side(TOPIC, False), "/move_base/parameter_updates", "dynamic_reconfigure/Config"),
    ]


def _rows(graph: LiveGraph) -> list[tuple[str, str, bool]]:
    server = planned(SERVER, "Planner", "params")
    plan = ContainerPlan("Cloud", "", [NodePlan("Cloud", "Planner", "/Planner", "launched",
                                                [server])])  # fmt: skip
    status = {"node": "/Planner", "interfaces": {"params": {"resolved": "/move_base",
                                                            "served": 2}}}  # fmt: skip
    found = compare(plan, graph, {"/Planner": status}, {})
    return [(row.interface, row.seen, row.ok) for row in found]


def test_a_served_part_is_checked_on_the_masters_services() -> None:
    graph = LiveGraph(
        publishers={"/move_base/parameter_updates": {"/Planner"}},
        services={"/move_base/set_parameters": {"/Planner"}},
        types={"/move_base/parameter_updates": "dynamic_reconfigure/Config"},
    )
    ((interface, seen, ok),) = _rows(graph)  # registered both ways, no unexpected row
    assert (interface, ok) == ("params", True) and "registered" not in seen and "type" not in seen
    unserved = replace(graph, services={})
    (row,) = _rows(unserved)
    assert row[1:] == ("not registered on /move_base/set_parameters", False)
    mistyped = replace(graph, types={"/move_base/parameter_updates": "std_msgs/Empty"})
    (row,) = _rows(mistyped)
    assert row[1:] == ("/move_base/parameter_updates type std_msgs/Empty", False)


def test_a_familys_calls_and_answers_are_said_in_its_words() -> None:
    """A client passes when its server answered it and sent it what else comes back."""
    client = replace(planned(CLIENT, "Tuner", "planner"), server="Cloud.Planner.params")
    served = {"resolved": "/move_base", "served": 3}
    reached = {"resolved": "/move_base", "answered_by": {"Cloud.Planner.params": 2},
               "feedback_from": {"Cloud.Planner.params": 4}}  # fmt: skip
    server = planned(SERVER, "Planner", "params")
    nodes = [NodePlan("Cloud", "Planner", "/Planner", "launched", [server]),
             NodePlan("Cloud", "Tuner", "/Tuner", "launched", [client])]  # fmt: skip
    graph = LiveGraph(
        publishers={"/move_base/parameter_updates": {"/Planner"}},
        subscribers={"/move_base/parameter_updates": {"/Tuner"}},
        services={"/move_base/set_parameters": {"/Planner"}},
        types={"/move_base/parameter_updates": "dynamic_reconfigure/Config"},
    )

    def rows(tuner: dict) -> list[tuple[str, str, str, bool]]:
        statuses = {"/Planner": {"interfaces": {"params": served}},
                    "/Tuner": {"interfaces": {"planner": tuner}}}  # fmt: skip
        found = compare(ContainerPlan("Cloud", "", nodes), graph, statuses, {})
        return [(r.interface, r.expected, r.seen, r.ok) for r in found]

    assert rows(reached) == [
        ("params", f"provides action {TYPE}", "provides action (3 reconfigurations answered)",
         True),
        ("planner", "answer and updates from Planner.params",
         "answered by Planner.params (2), updates from Planner.params (4)", True),
    ]  # fmt: skip
    unreached = {**reached, "feedback_from": {}}  # answered, but no update came back
    assert rows(unreached)[1][2:] == ("answered by Planner.params (2)", False)
