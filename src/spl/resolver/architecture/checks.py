"""Checks of a resolved architecture (docs/resolution.md, step 7) against its flow table.

A product can be valid for the feature model and still not work: a message type that
differs across a connection is an error; a subscriber no flow feeds or a service
client no flow serves is a warning (the data may come from outside the product), unless
the .tsm says what feeds it from outside (``external "why"``, docs/tsm.md).
Whether a flow reaches an input is the flow table's answer (:mod:`spl.resolver.architecture.flows`),
the one every output follows. Where the nodes run gives two more warnings, read from
the placement (:mod:`spl.resolver.architecture.placement`): a shared instance robots of two Rapyuta
users use (SPL047), a cloud container no robot reaches (SPL048).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Diagnostic, Severity, location_of
from spl.metamodels import tsm
from spl.metamodels.interface_kinds import InterfaceKind, kind_of
from spl.resolver.architecture.flows import CutRoute, FlowTable
from spl.resolver.architecture.placement import (
    SHARED_ACROSS_USERS,
    SHARED_MODES,
    Instance,
    Placement,
    links,
    rapyuta_user,
)
from spl.resolver.architecture.product import topic_ros_name
from spl.resolver.resolution.context import qualified

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

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


def awaits_feed(interface: tsm_types.Interface) -> bool:
    """Whether an interface is an input that goes without when no flow feeds it: a
    subscriber bound to a topic (one bound to none waits for nothing), or a client,
    bound or not (its calls go unanswered either way)."""
    kind = kind_of(interface)
    return _awaits(kind, kind.bound_to(interface))


def _awaits(kind: InterfaceKind, bound: object) -> bool:
    """:func:`awaits_feed` of an interface of ``kind`` bound to ``bound``."""
    return not kind.provides and (not kind.on_topic or bound is not None)


def input_gap(interface: tsm_types.Interface, flows: FlowTable) -> str | None:
    """The kind's unfed code (SPL045 for a node subscriber bound to a topic, SPL046 for
    a node client) when no flow of the product feeds the input, unless the model says
    what feeds it from outside (``external``, docs/tsm.md); None otherwise. The one
    verdict resolve, validate and the rehearsal give (docs/semantics.md F6), and the one
    ``spl check`` looks for in every product (F8)."""
    kind = kind_of(interface)
    return _gap(interface, kind, kind.bound_to(interface), flows)


def _gap(
    interface: tsm_types.Interface, kind: InterfaceKind, bound: object, flows: FlowTable
) -> str | None:
    """:func:`input_gap` of ``interface`` of ``kind`` bound to ``bound``: read once by
    :func:`check_architecture`, which asks each interface's kind and binding anyway."""
    # external last: unset on most interfaces, and pyecore makes a slot for each one read
    if not _awaits(kind, bound) or flows.feeding(interface) or interface.external:
        return None
    return kind.unfed_code


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
                kind = kind_of(interface)
                bound = kind.bound_to(interface)
                topic = bound if kind.on_topic else None  # bound_topic
                if topic is not None and interface.type and interface.type != topic.type:
                    report(
                        interface,
                        f"{qualified(interface)} is {interface.type} but topic "
                        f"{qualified(topic)} is {topic.type}",
                        "error",
                        "SPL044",
                    )
                gap = _gap(interface, kind, bound, flows)
                if gap is not None and topic is not None:
                    report(
                        interface,
                        f"{qualified(interface)} {kind.keyword} {qualified(topic)}, "
                        + unfed_reason(cast("tsm_types.Subscriber", interface), flows.cut + cut),
                        "warning",
                        gap,
                    )
                if kind.calls:
                    server = cast("tsm_types.ServiceServer | None", bound)
                    if gap is not None:
                        report(
                            interface,
                            f"{kind.title} {qualified(interface)} has no server in this product",
                            "warning",
                            gap,
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


def shared_across_users(system: tsm_types.System) -> list[Diagnostic]:
    """A warning for each shared cloud instance that robots of two Rapyuta users use.

    The model says they share one instance, and Kubernetes and Zenoh deploy one; but the
    engine keeps each user's containers apart, so on Rapyuta each user gets an instance
    of its own and the robots share nothing there (a yield map one robot builds never
    reaches the other). Tag problems are left to the generators, which report them."""
    logins = {id(c): user for c in system.containers if (user := rapyuta_user(c))}
    if len(set(logins.values())) < 2:
        return []  # one user (most lines): nothing to place
    placement = Placement(system, [])
    users = {placement.robot_ids[i]: user for i, user in logins.items()}
    problems = []
    for instance in _shared_instances(placement):
        using = [r for r in instance.robots if r in users]
        if not instance.place.shared or len({users[r] for r in using}) < 2:
            continue
        nodes = ", ".join(node.name for node in instance.nodes)
        robots = ", ".join(f"{r} (user {users[r]!r})" for r in using)
        problems.append(
            Diagnostic(
                location_of(instance.container),
                f"cloud container {instance.container.name}: its {instance.place.kind} nodes "
                f"({nodes}) run in one instance, {instance.place.tag}, for robots {robots}; "
                "the Rapyuta engine keeps each user's containers apart, so rapyuta/ gives "
                "each user an instance of its own and they share nothing there (kubernetes/ "
                "and zenoh/ deploy one): give these robots one user",
                "warning",
                SHARED_ACROSS_USERS,
            )
        )
    return problems


def _shared_instances(placement: Placement) -> list[Instance]:
    """The shared cloud instances, as :meth:`Placement.cloud_instances` lists them. Which
    private instances exist (costly to decide: their flows) matters only where one would
    take a shared one's tag: then every instance is placed."""
    shared = placement.cloud_instances(SHARED_MODES)
    private = {
        placement.place(cloud, "private", robot, claim=False).tag
        for robot in placement.robots
        for cloud in placement.scope(robot)
    }
    if private & {instance.place.tag for instance in shared}:
        return placement.cloud_instances()
    return shared


UNLINKED_CLOUD = "SPL048"


def unlinked_clouds(system: tsm_types.System) -> list[Diagnostic]:
    """A warning at each cloud container with nodes that no robot container reaches
    through endpoint connections (directly or through other clouds).

    A cloud instance is deployed for the robots that use it (Rapyuta declares it in a
    robot's file; Kubernetes deploys what some robot's scope holds), so such a container's
    nodes get a launch file and nothing that starts them: deployed by neither."""
    T = tsm()
    neighbours = links(system)
    reached = {id(c) for c in system.containers if isinstance(c, T.RobotContainer)}
    frontier = list(reached)
    while frontier:
        for neighbour in neighbours[frontier.pop()] - reached:
            reached.add(neighbour)
            frontier.append(neighbour)
    return [
        Diagnostic(
            location_of(cloud),
            f"cloud container {cloud.name} is linked to no robot container (no bridge joins "
            "it to one, directly or through other clouds): rapyuta/ and kubernetes/ deploy "
            f"none of its nodes ({', '.join(n.name for n in cloud.nodes)}); bridge it to the "
            "robot containers that use it",
            "warning",
            UNLINKED_CLOUD,
        )
        for cloud in system.containers
        if isinstance(cloud, T.CloudContainer) and cloud.nodes and id(cloud) not in reached
    ]
