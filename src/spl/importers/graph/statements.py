"""The ``.tsm`` statements of a live graph's topics and of each node's interfaces, shared
by ``spl import graph`` and ``spl import launch --graph`` so that both write a system's
topics alike (docs/import.md, "A live graph").

A topic is named by its ROS name (``/scan/raw`` is ``scan_raw``); an interface by the ROS
name it is bound to, which the generated launch file remaps it to, so the node's own
name for it does not matter. An action's client is bound to its server where both are
in the line: by ``->`` in one container, by a ``bridge`` across two (docs/tsm.md,
"Actions").
"""

from __future__ import annotations

from collections.abc import Iterable

from spl.dsl import rosnames
from spl.importers.graph.master import Graph, GraphNode
from spl.importers.naming import feature_name, string_literal

# where a node is in the written .tsm, by its ROS name: (container, node name)
Places = dict[str, tuple[str, str]]


def identifier(ros_name: str, taken: set[str]) -> str:
    return feature_name(ros_name.strip("/").replace("/", "_"), taken, f"t_{ros_name}")


def topic_statements(
    graph: Graph, nodes: Iterable[GraphNode], warnings: list[str]
) -> tuple[list[str], dict[str, str]]:
    """``topic`` statements for every topic ``nodes`` use, and their names by ROS name."""
    topics: dict[str, str] = {}
    lines = []
    for topic in sorted({t for n in nodes for t in n.publishes | n.subscribes}):
        kind = graph.topic_types.get(topic, "")
        if not rosnames.is_type(kind):
            warnings.append(f"warning: topic {topic} left out: its type {kind!r} is unknown")
            continue
        topics[topic] = identifier(topic, set(topics.values()))
        lines.append(f"topic {topics[topic]} : {kind} name {string_literal(topic)}")
    return lines, topics


def action_names(node: GraphNode) -> dict[str, str]:
    """The interface names of a node's actions, by ROS name. They are chosen before its
    other interfaces' (whose ROS names, a topic's or a service's, are never an action's),
    so that a client can name the interface of its server."""
    names: dict[str, str] = {}
    for action in sorted(node.serves_actions | node.calls_actions):
        names[action] = identifier(action, set(names.values()))
    return names


def interface_statements(
    graph: Graph, node: GraphNode, topics: dict[str, str], places: Places, bridges: list[str]
) -> list[str]:
    """``publishes``, ``subscribes``, ``provides`` and action statements of one node at
    ``places[node.name]``; the bridge of each action client whose server is in another
    container is added to ``bridges``."""
    lines: list[str] = []
    actions = action_names(node)
    taken: set[str] = set(actions.values())
    for verb, arrow, used in (("publishes", "->", node.publishes),
                              ("subscribes", "<-", node.subscribes)):  # fmt: skip
        for topic in sorted(used & topics.keys()):
            interface = identifier(topic, taken)
            taken.add(interface)
            lines.append(f"{verb} {interface} {arrow} {topics[topic]}")
    for service in sorted(node.serves):
        kind = graph.service_types.get(service, "")
        if rosnames.is_type(kind):  # else reported by the reading
            interface = identifier(service, taken)
            taken.add(interface)
            lines.append(f"provides {interface} : {kind} name {string_literal(service)}")
    for action in sorted(node.serves_actions):
        kind = graph.actions[action].type
        lines.append(f"provides action {actions[action]} : {kind} name {string_literal(action)}")
    for action in sorted(node.calls_actions):
        server = graph.actions[action].server
        statement = f"calls action {actions[action]} : {graph.actions[action].type}"
        here, there = places[node.name], places.get(server)
        if there is None:
            reason = f"served by {server}, which is not in the line"
            statement += f" external {string_literal(reason)}"
        else:
            target = f"{there[1]}.{action_names(graph.nodes[server])[action]}"
            if there[0] == here[0]:
                statement += f" -> {target}"
            else:
                bridges.append(f"bridge {'.'.join(here)}.{actions[action]} -> {there[0]}.{target}")
        lines.append(statement)
    return lines
