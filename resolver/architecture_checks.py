"""Checks of a resolved architecture (SPEC 5.1 step 8) on a networkx data-flow graph.

A product can be valid for the feature model and still not work: a message type that
differs across a connection is an error; a subscriber nothing feeds or a service
client nothing serves is a warning (the data may come from outside the product).
"""

from __future__ import annotations

from typing import Any

import networkx as nx

from spl.diagnostics import Diagnostic, location_of
from spl.metamodels import tsm
from spl.resolver.context import qualified
from spl.resolver.product import topic_ros_name

SOURCE = "publishers"


def data_flow_graph(system: Any) -> nx.DiGraph:
    """Node publishers -> topics -> subscribers, topics linked by endpoint connections."""
    T = tsm()
    graph = nx.DiGraph()
    graph.add_node(SOURCE)
    for container in system.containers:
        for node in container.nodes:
            for interface in node.interfaces:
                if isinstance(interface, T.Publisher) and interface.topic is not None:
                    graph.add_edge(SOURCE, id(interface.topic))
                elif isinstance(interface, T.Subscriber) and interface.topic is not None:
                    graph.add_edge(id(interface.topic), id(interface))
    for connection in system.connections:
        source, target = connection.source, connection.target
        if isinstance(source, T.Subscriber) and isinstance(target, T.Publisher):
            graph.add_edge(id(source.topic), id(target.topic))
    return graph


def check_architecture(system: Any) -> list[Diagnostic]:
    T = tsm()
    problems: list[Diagnostic] = []

    def report(element: Any, message: str, severity: str, code: str) -> None:
        problems.append(Diagnostic(location_of(element), message, severity, code))

    fed = nx.descendants(data_flow_graph(system), SOURCE)
    stores = {id(s) for c in system.containers for s in c.stores}
    for container in system.containers:
        for node in container.nodes:
            if not node.package and not isinstance(node, (T.Writer, T.Reader)):
                report(
                    node,
                    f"node {node.name} has no implementation in this product (give one in the "
                    ".tsm or with an implementation transformation)",
                    "error",
                    "SPL041",
                )
            if isinstance(node, (T.Writer, T.Reader)) and id(node.store) not in stores:
                report(
                    node,
                    f"{node.name} uses store {node.store.name}, which is not in this product",
                    "error",
                    "SPL042",
                )
            for parameter in node.parameters:
                if parameter.value is None:
                    report(
                        parameter,
                        f"parameter {node.name}.{parameter.name} has no value in this product",
                        "error",
                        "SPL043",
                    )
            for interface in node.interfaces:
                topic = getattr(interface, "topic", None)
                if topic is not None and interface.type and interface.type != topic.type:
                    report(
                        interface,
                        f"{qualified(interface)} is {interface.type} but topic "
                        f"{qualified(topic)} is {topic.type}",
                        "error",
                        "SPL044",
                    )
                unfed = isinstance(interface, T.Subscriber) and id(interface) not in fed
                if unfed and topic is not None:
                    report(
                        interface,
                        f"{qualified(interface)} subscribes {qualified(topic)}, which no "
                        "node of the product publishes",
                        "warning",
                        "SPL045",
                    )
                if isinstance(interface, T.ServiceClient):
                    server = interface.server
                    if server is None:
                        report(
                            interface,
                            f"service client {qualified(interface)} has no server in this product",
                            "warning",
                            "SPL046",
                        )
                    elif interface.type and server.type and interface.type != server.type:
                        report(
                            interface,
                            f"{qualified(interface)} is {interface.type} but its server "
                            f"{qualified(server)} is {server.type}",
                            "error",
                            "SPL044",
                        )
    for container in system.containers:  # a topic a .rm statement created, too
        by_ros_name: dict[str, Any] = {}
        for topic in container.topics:
            first = by_ros_name.setdefault(topic_ros_name(topic), topic)
            if first is not topic and first.type != topic.type:
                report(
                    topic,
                    f"topics {qualified(first)} and {qualified(topic)} are both "
                    f"{topic_ros_name(topic)} but carry {first.type} and {topic.type}: one "
                    "ROS topic carries one message type",
                    "error",
                    "SPL044",
                )
    for connection in system.connections:
        source, target = connection.source, connection.target
        if source.type != target.type:
            report(
                connection,
                f"endpoint connection {qualified(source)} -> {qualified(target)} joins "
                f"{source.type} and {target.type}",
                "error",
                "SPL044",
            )
    return problems
