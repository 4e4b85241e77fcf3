"""Which flows of a resolved architecture cross a deployment boundary (SPEC 5.2).

:mod:`spl.resolver.flows` says who talks to whom in the architecture, one row per
delivery; :mod:`spl.resolver.placement` says where each node runs: on a robot, or in
one sharing partition of a cloud container (a *place*). This module puts the two
together: a flow whose two nodes end up in different places is a :class:`Crossing`;
flows inside one place, and containers that only relay, cross nothing. Partitions of
one TSM container are different places too (a private MapOptimizer calling a protected
Database).

The flows are seen from one robot at a time, since a cloud container's private
partition is instantiated per robot: the robot, the cloud containers it uses and the
other robots linked to those. A private partition serves its own robot alone: a flow
between another robot and it is *withheld* in this robot's view (no crossing; the
other robot's own instance takes it), docs/semantics.md F4.

Every deployment target that carries data between places takes its wiring from here
(Rapyuta bridges; Kubernetes services and Zenoh allow lists likewise), so they agree.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from spl.diagnostics import Diagnostic, location_of
from spl.resolver.flows import TOPIC, Flow, FlowTable, container_of
from spl.resolver.placement import Place, Placement
from spl.resolver.ros_names import resolved_service_name, resolved_topic_name


@dataclass(frozen=True)
class Crossing:
    """One flow between two places: data published at ``source`` is consumed at
    ``target`` (``kind`` "topic"), or a client at ``source`` calls a server at
    ``target`` (``kind`` "service")."""

    kind: str
    source: Place
    target: Place
    source_element: Any  # topic: the Topic published on; service: the calling ServiceClient
    target_element: Any  # topic: the Topic subscribed to; service: the real ServiceServer
    source_name: str  # the ROS name at the source, in its container's namespace
    target_name: str  # the ROS name at the target, in its container's namespace


class Wiring:
    """The crossings of one resolved system, as each robot's deployment sees them.

    Problems (a subscriber fed a message type it does not expect) are appended to
    ``errors``, located in the model, when the flow is reached.
    """

    def __init__(self, flows: FlowTable, placement: Placement, errors: list[Diagnostic]) -> None:
        self.flows = flows
        self.placement = placement
        self.errors = errors

    def view(self, robot: Any) -> list[Any]:
        """The containers ``robot``'s deployment sees: itself, the clouds it uses and the
        robots linked to those."""
        placement = self.placement
        allowed = {id(robot)} | {id(c) for c in placement.scope(robot)}
        for container_id in list(allowed):
            allowed |= {
                n
                for n in placement.neighbours[container_id]
                if placement.is_robot(placement.by_id[n])
            }
        return [c for c in placement.by_id.values() if id(c) in allowed]

    def deliveries(self, robot: Any) -> Iterator[Delivery]:
        """Every flow between two containers of ``robot``'s view, placed, in table
        order; ``withheld`` when a private partition would serve another robot."""
        placement = self.placement
        robot_id = placement.robot_ids[id(robot)]
        allowed = {id(c) for c in self.view(robot)}

        def foreign(place: Place) -> bool:
            return place.is_robot and place.owner != robot_id

        for flow in self.flows:
            if id(flow.source_container) not in allowed or id(flow.target_container) not in allowed:
                continue
            source = placement.node_place(flow.source.eContainer(), robot)
            target = placement.node_place(flow.target.eContainer(), robot)
            withheld = (foreign(source) and target.kind == "private") or (
                foreign(target) and source.kind == "private"
            )
            yield Delivery(flow, source, target, withheld)

    def crossings(self, robot: Any) -> Iterator[Crossing]:
        """The crossings of the system instantiated for ``robot``: topics first (by
        publisher, then subscriber, in model order), then service calls (by client)."""
        system = self.placement.system
        for delivery in self.deliveries(robot):
            flow, producer, consumer = delivery.flow, delivery.source, delivery.target
            if delivery.withheld:
                continue
            if flow.kind == TOPIC:
                source_topic, target_topic = flow.source.topic, flow.target.topic
                source_name = resolved_topic_name(source_topic)
                target_name = resolved_topic_name(target_topic)
                if producer == consumer and source_name == target_name:
                    continue
                if source_topic.type != target_topic.type:
                    self.errors.append(
                        Diagnostic(
                            location_of(flow.target),
                            f"{flow.source.eContainer().name}.{flow.source.name} feeds "
                            f"{flow.target.eContainer().name}.{flow.target.name} with "
                            f"{source_topic.type} but it expects {target_topic.type}",
                        )
                    )
                    continue
                yield Crossing(
                    "topic", producer, consumer, source_topic, target_topic,
                    source_name, target_name,
                )  # fmt: skip
            elif producer != consumer:
                client, server = flow.source, flow.target
                yield Crossing(
                    "service",
                    producer,
                    consumer,
                    client,
                    server,
                    resolved_service_name(client.server, container_of(client), system),
                    resolved_service_name(server, container_of(server), system),
                )


@dataclass(frozen=True)
class Delivery:
    """A flow as one robot's deployment places it."""

    flow: Flow
    source: Place
    target: Place
    withheld: bool  # a private partition and another robot: not delivered in this view
