"""Which flows of a resolved architecture cross a deployment boundary (docs/deployment.md).

:mod:`spl.resolver.architecture.flows` says who talks to whom in the architecture, one row per
delivery; :mod:`spl.resolver.architecture.placement` says where each node runs: on a robot, or in
one sharing partition of a cloud container (a *place*). This module puts the two
together: a flow whose two nodes end up in different places is a :class:`Crossing`;
flows inside one place, and containers that only relay, cross nothing. Partitions of
one TSM container are different places too (a private MapOptimizer calling a protected
Database).

The flows are seen from one robot at a time, since a cloud container's private
partition is instantiated per robot: the robot, the cloud containers it uses and the
other robots linked to those. A private partition serves its own robot alone: a flow
between another robot and it is *withheld* in this robot's view (no crossing; the
other robot's own instance takes it), docs/semantics.md F4; so is a flow at a private
node the robot gets no instance of (:mod:`spl.resolver.architecture.private_instances`).

Every deployment target that carries data between places takes its wiring from here
(Rapyuta bridges; Kubernetes services and Zenoh allow lists likewise), so they agree.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Diagnostic, location_of
from spl.metamodels import tsm
from spl.metamodels.interface_kinds import Family
from spl.resolver.architecture.flows import Flow, FlowTable, container_of, node_of
from spl.resolver.architecture.placement import Place, Placement, sharing_mode
from spl.resolver.architecture.private_instances import Delivery, placed_flows
from spl.resolver.architecture.ros_names import resolved_service_name, resolved_topic_name
from spl.resolver.resolution.context import qualified
from spl.resolver.resolution.trace import Trace

if TYPE_CHECKING:
    from spl.metamodels import tsm_types


@dataclass(frozen=True)
class Crossing:
    """One flow between two places: data published at ``source`` is consumed at
    ``target`` (``kind`` on a topic, TOPIC), or a client at ``source`` calls a server at
    ``target`` (``kind`` a call family, SERVICE); ``kind`` is its flow's."""

    kind: Family
    source: Place
    target: Place
    # topic: the Topic published on; service: the calling ServiceClient
    source_element: tsm_types.Topic | tsm_types.ServiceClient
    # topic: the Topic subscribed to; service: the real ServiceServer
    target_element: tsm_types.Topic | tsm_types.ServiceServer
    source_name: str  # the ROS name at the source, in its container's namespace
    target_name: str  # the ROS name at the target, in its container's namespace
    flow: Flow = field(compare=False)  # the flow table's row it carries


class Wiring:
    """The crossings of one resolved system, as each robot's deployment sees them.

    Problems (a subscriber fed a message type it does not expect) are appended to
    ``errors``, located in the model, when the flow is reached.
    """

    def __init__(self, flows: FlowTable, placement: Placement, errors: list[Diagnostic]) -> None:
        self.flows = flows
        self.placement = placement
        self.errors = errors

    def deliveries(self, robot: tsm_types.Container) -> Iterator[Delivery]:
        """Every flow between two containers of ``robot``'s view, placed, in table
        order; ``withheld`` when a private partition would serve another robot, or when
        the robot gets no instance of a private node at one end (docs/deployment.md,
        "Private instances")."""
        placement = self.placement
        for delivery in placed_flows(placement, self.flows, robot):
            if delivery.withheld:
                yield delivery
                continue
            source, target = node_of(delivery.flow.source), node_of(delivery.flow.target)
            if not (placement.deploys(source, robot) and placement.deploys(target, robot)):
                yield replace(delivery, withheld=True)
                continue
            placement.node_place(source, robot)  # its tag taken, as a deployed instance's
            placement.node_place(target, robot)
            yield delivery

    def crossings(self, robot: tsm_types.Container) -> Iterator[Crossing]:
        """The crossings of the system instantiated for ``robot``: topics first (by
        publisher, then subscriber, in model order), then service calls (by client)."""
        system = self.placement.system
        for delivery in self.deliveries(robot):
            flow, producer, consumer = delivery.flow, delivery.source, delivery.target
            if delivery.withheld:
                continue
            if flow.kind.on_topic:
                publisher = cast("tsm_types.Publisher", flow.source)
                subscriber = cast("tsm_types.Subscriber", flow.target)
                # a topic flow's ends are bound (spl.resolver.architecture.flows)
                source_topic = cast("tsm_types.Topic", publisher.topic)
                target_topic = cast("tsm_types.Topic", subscriber.topic)
                source_name = resolved_topic_name(source_topic)
                target_name = resolved_topic_name(target_topic)
                if producer == consumer and source_name == target_name:
                    continue
                if source_topic.type != target_topic.type:
                    self.errors.append(
                        Diagnostic(
                            location_of(flow.target),
                            f"{node_of(flow.source).name}.{flow.source.name} feeds "
                            f"{node_of(flow.target).name}.{flow.target.name} with "
                            f"{source_topic.type} but it expects {target_topic.type}",
                        )
                    )
                    continue
                yield Crossing(
                    flow.kind, producer, consumer, source_topic, target_topic,
                    source_name, target_name, flow,
                )  # fmt: skip
            elif producer != consumer:
                client = cast("tsm_types.ServiceClient", flow.source)
                server = cast("tsm_types.ServiceServer", flow.target)
                yield Crossing(
                    flow.kind,
                    producer,
                    consumer,
                    client,
                    server,
                    # (a service flow's client is bound: to the server or a stand-in)
                    resolved_service_name(
                        cast("tsm_types.ServiceServer", client.server), container_of(client), system
                    ),
                    resolved_service_name(server, container_of(server), system),
                    flow,
                )


CROSS_ROBOT = "SPL050"


@dataclass(frozen=True)
class CutOff:
    """A robot interface (``taker``) fed by ``giver`` of a private cloud node whose
    instance for that robot takes nothing from it, while other robots' data reaches the
    node: ``feeders`` are those robots, each with the flow its data takes in."""

    taker: tsm_types.Interface
    giver: tsm_types.Interface
    robot: tsm_types.Container
    feeders: tuple[tuple[tsm_types.Container, Flow], ...]


def cut_off(flows: FlowTable, private: Callable[[tsm_types.Node], bool]) -> list[CutOff]:
    """Every :class:`CutOff` of a flow table, ``private`` saying which cloud nodes are
    private (one instance per robot), in table order, once per taker and node."""
    T = tsm()

    def on_robot(interface: tsm_types.Interface) -> tsm_types.Container | None:
        owner = container_of(interface)
        return owner if isinstance(owner, T.RobotContainer) else None

    lone: dict[int, bool] = {}  # id(interface) -> alone(interface), asked once each

    def alone(interface: tsm_types.Interface) -> bool:
        found = lone.get(id(interface))
        if found is None:
            found = on_robot(interface) is None and private(node_of(interface))
            lone[id(interface)] = found
        return found

    # who gives data to whom: a publisher to a subscriber, a server's answers to its client
    given: list[tuple[Flow, tsm_types.Interface, tsm_types.Interface]] = [
        (f, f.provider, f.consumer) for f in flows
    ]
    # id(node) -> id(robot) -> (robot, why)
    feeders: dict[int, dict[int, tuple[tsm_types.Container, Flow]]] = defaultdict(dict)
    for flow, giver, taker in given:
        robot = on_robot(giver)
        if robot is not None and alone(taker):
            feeders[id(taker.eContainer())].setdefault(id(robot), (robot, flow))
    chained = [(giver, taker) for _, giver, taker in given if alone(giver) and alone(taker)]
    changed = True
    while changed:  # through chains of private nodes: one robot's instances feed each other
        changed = False
        for giver, taker in chained:
            into = feeders[id(taker.eContainer())]
            before = len(into)
            for robot_id, why in list(feeders[id(giver.eContainer())].items()):
                into.setdefault(robot_id, why)
            changed |= len(into) != before
    found: dict[tuple[int, int], CutOff] = {}
    for _, giver, taker in given:
        robot, others = on_robot(taker), feeders.get(id(giver.eContainer()), {})
        if robot is not None and alone(giver) and others and id(robot) not in others:
            key = (id(taker), id(giver.eContainer()))
            found.setdefault(key, CutOff(taker, giver, robot, tuple(others.values())))
    return list(found.values())


def cross_robot_flows(system: tsm_types.System, flows: FlowTable, trace: Trace) -> list[Diagnostic]:
    """A warning (SPL050) at each robot interface that a private cloud node feeds from an
    instance nothing of that robot feeds, while another robot's data reaches the node
    (directly or through other private nodes): one instance per robot, so that data
    never crosses to this robot, though the template draws the flow (docs/semantics.md
    F4)."""
    if sum(c.eClass.name == "RobotContainer" for c in system.containers) < 2:
        return []
    return [
        cross_robot_warning(cut, _private_because(node_of(cut.giver), trace))
        for cut in cut_off(flows, lambda node: sharing_mode(node) == "private")
    ]


def cross_robot_warning(cut: CutOff, why_private: str) -> Diagnostic:
    node, robot = node_of(cut.giver), cut.robot
    fed_by = "; ".join(f"{other.name} ({why.describe()})" for other, why in cut.feeders)
    return Diagnostic(
        location_of(cut.taker),
        f"{qualified(cut.taker)} on robot container {robot.name} is fed by "
        f"{qualified(cut.giver)} of its own instance of {node.name}, which {why_private}: "
        f"one instance per robot, and the data {node.name} takes from robot container "
        f"{fed_by} reaches only that robot's instance, never {robot.name}; share "
        f"{node.name} (protected or public) or feed it from {robot.name} too",
        "warning",
        CROSS_ROBOT,
    )


def _private_because(node: tsm_types.Node, trace: Trace) -> str:
    """Why a node is private in this product: the feature's sharing mode, or the .tsm."""
    decision = next(
        (e for e in trace.entries if e.subject == node.name and e.decision == "sharing"), None
    )
    if decision is not None:
        return f"is {decision.reason}"
    return f"is private as the .tsm gives it (declared, or the default; {location_of(node)})"
