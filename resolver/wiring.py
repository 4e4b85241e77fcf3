"""Which data flows of a resolved architecture cross a deployment boundary (SPEC 5.2).

:mod:`spl.resolver.placement` says where each node runs: on a robot, or in one sharing
partition of a cloud container (a *place*). This module follows every data flow of the
architecture from the node that produces it to each node that consumes it: a
publisher's topic, across endpoint connections, to the subscribers of every topic
reached; a client, through any chain of endpoint stand-ins, to the real server. A flow
whose two nodes end up in different places is a :class:`Crossing`; flows inside one
place, and containers that only relay, cross nothing. Partitions of one TSM container
are different places too (a private MapOptimizer calling a protected Database).

The flows are seen from one robot at a time, since a cloud container's private
partition is instantiated per robot: the robot, the cloud containers it uses and the
other robots linked to those. A private partition serves its own robot alone: data of
another robot reaches it, or leaves it for another robot, only through a shared
partition's nodes, so such a flow is no crossing in this robot's view.

Every deployment target that carries data between places takes its wiring from here
(Rapyuta bridges; Kubernetes services and Zenoh allow lists likewise), so they agree.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from spl.diagnostics import Diagnostic, location_of
from spl.resolver.placement import Place, Placement, container_of
from spl.resolver.product import NodeInterfaces
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

    Problems (a subscriber fed a message type it does not expect; the tag clashes the
    placement finds) are appended to ``errors``, located in the model, when the flow
    is reached.
    """

    def __init__(self, system: Any, placement: Placement, errors: list[Diagnostic]) -> None:
        self.system = system
        self.placement = placement
        self.errors = errors
        T = placement.T
        self.topic_edges: dict[int, list[Any]] = defaultdict(list)
        self.callers_of: dict[int, list[Any]] = defaultdict(list)
        for connection in system.connections:
            source, target = connection.source, connection.target
            if isinstance(source, T.Subscriber) and isinstance(target, T.Publisher):
                if source.topic is not None and target.topic is not None:
                    self.topic_edges[id(source.topic)].append(target.topic)
            elif isinstance(source, T.ServiceServer) and isinstance(target, T.ServiceClient):
                self.callers_of[id(source)].append(target)

    def crossings(self, robot: Any) -> Iterator[Crossing]:
        """The crossings of the system instantiated for ``robot``: topics first (by
        publisher, then subscriber, in model order), then service calls (by client)."""
        placement = self.placement
        robot_id = placement.robot_ids[id(robot)]
        allowed = {id(robot)} | {id(c) for c in placement.scope(robot)}
        for container_id in list(allowed):
            allowed |= {
                n
                for n in placement.neighbours[container_id]
                if placement.is_robot(placement.by_id[n])
            }
        members = [c for c in self.system.containers if id(c) in allowed]

        publishers, subscribers, all_clients = NodeInterfaces.of(members)
        clients = [client for client in all_clients if client.server is not None]
        subscribers_of: dict[int, list[Any]] = defaultdict(list)
        for subscriber in subscribers:
            subscribers_of[id(subscriber.topic)].append(subscriber)

        def foreign(place: Place) -> bool:
            return place.is_robot and place.owner != robot_id

        def serves(a: Place, b: Place) -> bool:
            """False when a private partition would serve another robot."""
            return not (
                (foreign(a) and b.kind == "private") or (foreign(b) and a.kind == "private")
            )

        for publisher in publishers:
            node = publisher.eContainer()
            producer = placement.node_place(node, robot)
            for topic in self._reached(publisher.topic, node.eContainer(), allowed):
                for subscriber in subscribers_of.get(id(topic), ()):
                    consumer = placement.node_place(subscriber.eContainer(), robot)
                    source_topic, target_topic = publisher.topic, subscriber.topic
                    source_name = resolved_topic_name(source_topic)
                    target_name = resolved_topic_name(target_topic)
                    if producer == consumer and source_name == target_name:
                        continue
                    if source_topic.type != target_topic.type:
                        self.errors.append(
                            Diagnostic(
                                location_of(subscriber),
                                f"{node.name}.{publisher.name} feeds "
                                f"{subscriber.eContainer().name}.{subscriber.name} with "
                                f"{source_topic.type} but it expects {target_topic.type}",
                            )
                        )
                        continue
                    if serves(producer, consumer):
                        yield Crossing(
                            "topic",
                            producer,
                            consumer,
                            source_topic,
                            target_topic,
                            source_name,
                            target_name,
                        )

        for client in clients:
            node = client.eContainer()
            server = self._real_server(client.server, allowed)
            if server is None:
                continue
            caller_place = placement.node_place(node, robot)
            server_node = server.eContainer()
            server_place = placement.node_place(server_node, robot)
            if caller_place == server_place or not serves(caller_place, server_place):
                continue
            yield Crossing(
                "service",
                caller_place,
                server_place,
                client,
                server,
                resolved_service_name(client.server, node.eContainer(), self.system),
                resolved_service_name(server, server_node.eContainer(), self.system),
            )

    def _reached(self, start: Any, home: Any, allowed: set[int]) -> list[Any]:
        """Topics data published on ``start`` arrives at; only clouds and home relay."""
        placement = self.placement
        seen = {id(start): start}
        frontier = [start]
        while frontier:
            topic = frontier.pop()
            container = topic.eContainer()
            if placement.is_robot(container) and container is not home:
                continue
            for target in self.topic_edges.get(id(topic), ()):
                if id(target.eContainer()) in allowed and id(target) not in seen:
                    seen[id(target)] = target
                    frontier.append(target)
        return list(seen.values())

    def _real_server(self, server: Any, allowed: set[int]) -> Any:
        """The node's ServiceServer behind a chain of endpoint stand-ins, if in view."""
        T = self.placement.T
        seen: set[int] = set()
        while server is not None and not isinstance(server.eContainer(), T.Node):
            if id(server) in seen:
                return None
            seen.add(id(server))
            callers = [
                c for c in self.callers_of.get(id(server), ()) if id(container_of(c)) in allowed
            ]
            server = callers[0].server if callers else None
        if server is None or id(server.eContainer().eContainer()) not in allowed:
            return None
        return server
