"""The ``.tsm`` statements of a live graph's topics and of each node's interfaces, shared
by ``spl import graph`` and ``spl import launch --graph`` so that both write a system's
topics alike (docs/import.md, "A live graph").

A topic is named by its ROS name (``/scan/raw`` is ``scan_raw``); an interface by the ROS
name it is bound to, which the generated launch file remaps it to, so the node's own
name for it does not matter.
"""

from __future__ import annotations

from collections.abc import Iterable

from spl.dsl import rosnames
from spl.importers.graph.master import Graph, GraphNode
from spl.importers.naming import feature_name, string_literal


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


def interface_statements(graph: Graph, node: GraphNode, topics: dict[str, str]) -> list[str]:
    """``publishes``, ``subscribes`` and ``provides`` statements of one node."""
    lines: list[str] = []
    taken: set[str] = set()
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
    return lines
