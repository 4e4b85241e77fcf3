"""Checks of a resolved architecture (docs/resolution.md, step 7) against its flow table.

A product can be valid for the feature model and still not work: a message type that
differs across a connection is an error; a subscriber no flow feeds or a service
client no flow serves is a warning (the data may come from outside the product), unless
the .tsm says what feeds it from outside (``external "why"``, docs/tsm.md).
Whether a flow reaches an input is the flow table's answer (:mod:`spl.resolver.flows`),
the one every output follows.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

from spl.diagnostics import Diagnostic, Severity, location_of
from spl.metamodels import tsm
from spl.resolver.context import qualified
from spl.resolver.flows import CutRoute, FlowTable
from spl.resolver.product import topic_ros_name

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

UNFED = "SPL045"
UNSERVED = "SPL046"
TWICE = "SPL051"


def unfed_reason(interface: tsm_types.Subscriber, cut_routes: tuple[CutRoute, ...]) -> str:
    """Why no flow reaches a subscriber: nothing publishes, or only through a robot that
    passes on no data but its own."""
    cut = next((c for c in cut_routes if c.subscriber is interface), None)
    if cut is None:
        return "which no node of the product publishes"
    return (
        f"which only {qualified(cut.publisher)} publishes, through robot container "
        f"{cut.robot.name}; a robot passes on no data but its own"
    )


def input_gap(interface: tsm_types.Interface, flows: FlowTable) -> str | None:
    """UNFED for a node subscriber bound to a topic that no flow of the product feeds,
    UNSERVED for a node client no flow takes to a server, unless the model says what
    feeds it from outside (``external``, docs/tsm.md); None otherwise. The one verdict
    resolve, validate and the rehearsal give (docs/semantics.md F6), and the one
    ``spl check`` looks for in every product (F8)."""
    T = tsm()
    if interface.external:
        return None
    if isinstance(interface, T.Subscriber):
        return UNFED if interface.topic is not None and not flows.feeding(interface) else None
    if isinstance(interface, T.ServiceClient):
        return UNSERVED if not flows.feeding(interface) else None
    return None


def check_architecture(
    system: tsm_types.System, flows: FlowTable, cut: tuple[CutRoute, ...] = ()
) -> list[Diagnostic]:
    """The problems of a resolved architecture; ``cut`` are the template's routes that a
    robot relay would have needed (what the endpoint rewiring left out, and why)."""
    T = tsm()
    problems: list[Diagnostic] = []

    def report(element: tsm_types.Located, message: str, severity: Severity, code: str) -> None:
        problems.append(Diagnostic(location_of(element), message, severity, code))

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
                topic: tsm_types.Topic | None = getattr(interface, "topic", None)
                if topic is not None and interface.type and interface.type != topic.type:
                    report(
                        interface,
                        f"{qualified(interface)} is {interface.type} but topic "
                        f"{qualified(topic)} is {topic.type}",
                        "error",
                        "SPL044",
                    )
                gap = input_gap(interface, flows)
                if gap == UNFED and topic is not None:
                    report(
                        interface,
                        f"{qualified(interface)} subscribes {qualified(topic)}, "
                        + unfed_reason(cast("tsm_types.Subscriber", interface), flows.cut + cut),
                        "warning",
                        UNFED,
                    )
                if isinstance(interface, T.ServiceClient):
                    server = interface.server
                    if gap == UNSERVED:
                        report(
                            interface,
                            f"service client {qualified(interface)} has no server in this product",
                            "warning",
                            UNSERVED,
                        )
                    elif (
                        server and interface.type and server.type and interface.type != server.type
                    ):
                        report(
                            interface,
                            f"{qualified(interface)} is {interface.type} but its server "
                            f"{qualified(server)} is {server.type}",
                            "error",
                            "SPL044",
                        )
    for container in system.containers:  # a topic a .rm statement created, too
        by_ros_name: dict[str, tsm_types.Topic] = {}
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
    for flow in flows.twice():
        report(
            flow.target,
            f"{qualified(flow.target)} gets the data of {qualified(flow.source)} along two "
            f"chains of bridges or more (the first: {flow.describe()}): the architecture "
            "delivers each message twice; the deployments and the rehearsal carry it once, "
            "along the first; remove the bridges of the others",
            "warning",
            TWICE,
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
