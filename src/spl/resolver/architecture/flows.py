"""Who talks to whom in an architecture: the flow table (docs/semantics.md, "Flows").

A *flow* is one delivery the architecture makes: the data a node publisher puts on its
topic reaching a node subscriber, or the calls of a node service client reaching the
node server that answers them. A flow names its two node interfaces and the *route*
between them: the endpoint connections (bridges) the data or the calls cross, in
order. Fan-out, fan-in and a server called from several containers are ordinary rows.

The rules a route follows, once, here:

- Topic data travels from the publisher's topic along every endpoint connection whose
  endpoint subscriber is on a topic it reached (the connection's endpoint publisher
  puts it on the peer topic), never twice onto one topic.
- A robot container relays only its own data: data arriving on a robot's topic from
  elsewhere is delivered to that robot's subscribers and goes no further. A route that
  would need another robot to pass the data on is *cut* (:attr:`FlowTable.cut`).
- A client's calls go to the server it is bound to; an endpoint stand-in server passes
  them over its connection to the endpoint client of the peer container, which calls
  the server it is bound to there, until a node's server answers.

Every target that moves data reads this table (the rehearsal's relays and
expectations, the architecture checks, the deployment targets through
:mod:`spl.resolver.architecture.wiring`, the diagram, ``spl explain``), and the endpoint rewiring
reads the template's table to keep its flows, so they cannot disagree about who talks
to whom.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple, cast

from spl.metamodels import tsm
from spl.metamodels.interface_kinds import SERVICE as SERVICE, TOPIC, Family, kind_of

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

Route = tuple["tsm_types.EndpointConnection", ...]


class NodeInterfaces(NamedTuple):
    """The wired interfaces of the nodes of some containers, by kind: the starting point
    of every data-flow walk (rewiring, Rapyuta bridges). Endpoint interfaces are not
    node interfaces and are not included."""

    publishers: tuple[tsm_types.Publisher, ...]  # bound to a topic
    subscribers: tuple[tsm_types.Subscriber, ...]  # bound to a topic
    clients: tuple[tsm_types.ServiceClient, ...]  # every service client, bound or not

    @classmethod
    def of(cls, containers: Iterable[tsm_types.Container]) -> NodeInterfaces:
        publishers: list[tsm_types.Publisher] = []
        subscribers: list[tsm_types.Subscriber] = []
        clients: list[tsm_types.ServiceClient] = []
        for container in containers:
            for node in container.nodes:
                for interface in node.interfaces:
                    kind = kind_of(interface)
                    if kind.calls:
                        clients.append(cast("tsm_types.ServiceClient", interface))
                    elif kind.publishes and kind.bound_to(interface) is not None:
                        publishers.append(cast("tsm_types.Publisher", interface))
                    elif kind.subscribes and kind.bound_to(interface) is not None:
                        subscribers.append(cast("tsm_types.Subscriber", interface))
        return cls(tuple(publishers), tuple(subscribers), tuple(clients))


# id(topic) -> (endpoint connection, the topic it puts the data on), for each connection
# whose endpoint subscriber is on the topic
Edges = dict[int, list[tuple["tsm_types.EndpointConnection", "tsm_types.Topic"]]]
Callers = dict[int, list["tsm_types.EndpointConnection"]]  # id(stand-in server) -> connections
Reached = tuple["tsm_types.Topic", "tsm_types.Container"]  # a topic, the robot relaying to it


def topic_of(interface: tsm_types.Publisher | tsm_types.Subscriber) -> tsm_types.Topic:
    """The topic of an interface bound to one (those :class:`NodeInterfaces` lists)."""
    return cast("tsm_types.Topic", interface.topic)


def bound_topic(interface: tsm_types.Interface) -> tsm_types.Topic | None:
    """The topic an interface is bound to; None if none, or of a kind on no topic."""
    kind = kind_of(interface)
    return cast("tsm_types.Topic | None", kind.bound_to(interface)) if kind.on_topic else None


def node_of(interface: tsm_types.Interface) -> tsm_types.Node:
    """The node of a node interface (a flow's ends are node interfaces)."""
    return cast("tsm_types.Node", interface.eContainer())


def container_of(interface: tsm_types.Interface) -> tsm_types.Container:
    """The container of a node interface or of an endpoint interface."""
    return interface.eContainer().eContainer()


@dataclass(frozen=True, eq=False)
class Flow:
    """One delivery: ``source`` (a node Publisher, or a node ServiceClient) reaches
    ``target`` (a node Subscriber, or the node ServiceServer answering) over ``route``.

    ``routes`` counts the distinct routes that deliver it, up to 2: a topic flow with 2
    reaches its subscriber twice (two chains of bridges carry the same message)."""

    kind: Family  # TOPIC or SERVICE
    source: tsm_types.Publisher | tsm_types.ServiceClient
    target: tsm_types.Subscriber | tsm_types.ServiceServer
    route: Route  # the EndpointConnections crossed, in travel order
    routes: int = 1

    @property
    def provider(self) -> tsm_types.Interface:
        """The end the data or the answers come from: the publisher, or the server."""
        return self.source if self.kind.flows_from_provider else self.target

    @property
    def consumer(self) -> tsm_types.Interface:
        """The end that depends on the flow: the subscriber, or the client it answers."""
        return self.target if self.kind.flows_from_provider else self.source

    @property
    def source_container(self) -> tsm_types.Container:
        return container_of(self.source)

    @property
    def target_container(self) -> tsm_types.Container:
        return container_of(self.target)

    def hops(self) -> list[tsm_types.Container]:
        """The containers the flow passes, from the source's to the target's."""
        return [self.source_container, *(container_of(c.target) for c in self.route)]

    def describe(self) -> str:
        """The flow in words: ``Camera.image -> Detector.image via Robot.Img -> Cloud.Img``."""
        arrow = f"{_name(self.source)} -> {_name(self.target)}"
        if not self.route:
            return f"{arrow} (in {self.source_container.name})"
        return f"{arrow} via {', '.join(_bridge(c) for c in self.route)}"


def _name(interface: tsm_types.Interface) -> str:
    return f"{container_of(interface).name}.{node_of(interface).name}.{interface.name}"


def _bridge(connection: tsm_types.EndpointConnection) -> str:
    source, target = connection.source, connection.target
    source_topic, target_topic = bound_topic(source), bound_topic(target)
    if source_topic is not None and target_topic is not None:
        return (
            f"{container_of(source).name}.{source_topic.name} -> "
            f"{container_of(target).name}.{target_topic.name}"
        )
    return f"{container_of(source).name} -> {container_of(target).name}"


@dataclass(frozen=True)
class CutRoute:
    """A topic flow the template draws through a robot that would have to relay another
    container's data: ``publisher``'s data reaches ``subscriber`` only through
    ``robot``."""

    publisher: tsm_types.Publisher
    subscriber: tsm_types.Subscriber
    robot: tsm_types.Container


class FlowTable:
    """Every flow of one architecture, in model order (topic flows by publisher, then
    by the order their topics are reached, then by subscriber; service flows by client),
    with look-ups by interface and by endpoint connection."""

    def __init__(
        self, flows: list[Flow], cut: list[CutRoute], unserved: list[tsm_types.ServiceClient]
    ) -> None:
        self.flows = tuple(flows)
        self.cut = tuple(cut)
        self.unserved = tuple(unserved)  # clients whose chain of stand-ins reaches no server
        self._at: dict[int, list[Flow]] = defaultdict(list)
        self._through: dict[int, list[Flow]] = defaultdict(list)
        for flow in self.flows:
            self._at[id(flow.source)].append(flow)
            self._at[id(flow.target)].append(flow)
            for connection in flow.route:
                self._through[id(connection)].append(flow)

    def __iter__(self) -> Iterator[Flow]:
        return iter(self.flows)

    def __len__(self) -> int:
        return len(self.flows)

    def at(self, interface: tsm_types.Interface) -> list[Flow]:
        """The flows with ``interface`` at one end."""
        return self._at.get(id(interface), [])

    def feeding(self, interface: tsm_types.Interface) -> list[Flow]:
        """The flows an input depends on: those delivering to a subscriber, or the one
        taking a client's calls to its server."""
        return [f for f in self.at(interface) if interface is f.consumer]

    def through(self, connection: tsm_types.EndpointConnection) -> list[Flow]:
        """The flows an endpoint connection carries."""
        return self._through.get(id(connection), [])

    def twice(self) -> list[Flow]:
        """Topic flows whose data reaches the subscriber by two routes or more."""
        return [f for f in self.flows if f.routes > 1]

    @classmethod
    def of(cls, system: tsm_types.System) -> FlowTable:
        """The flow table of ``system`` as its connections stand now. Node interfaces
        may still point at topics of the container their node left (the template's
        flows, which the endpoint rewiring keeps): a route starts at the topic the
        publisher is bound to, wherever that is."""
        T = tsm()
        edges, callers = _connections(system)
        publishers, subscribers, clients = NodeInterfaces.of(system.containers)
        subscribers_of: dict[int, list[tsm_types.Subscriber]] = defaultdict(list)
        for subscriber in subscribers:
            subscribers_of[id(subscriber.topic)].append(subscriber)

        flows: list[Flow] = []
        cut: list[CutRoute] = []
        walks: dict[int, _Walk] = {}
        for publisher in publishers:
            walk = walks.get(id(publisher.topic))
            if walk is None:
                start = cast("tsm_types.Topic", publisher.topic)  # bound: NodeInterfaces
                walk = walks[id(start)] = _Walk(start, edges, T)
            for topic in walk.order:
                for subscriber in subscribers_of.get(id(topic), ()):
                    flows.append(
                        Flow(TOPIC, publisher, subscriber, walk.route(topic), walk.count(topic))
                    )
            for topic, robot in walk.beyond:
                cut += [CutRoute(publisher, s, robot) for s in subscribers_of.get(id(topic), ())]

        unserved = []
        for client in clients:
            if client.server is None:
                continue
            server, route = _answering(client.server, callers, T)
            if server is None:
                unserved.append(client)
            else:
                flows.append(Flow(kind_of(client).family, client, server, route))
        return cls(flows, cut, unserved)


def reached_topics(system: tsm_types.System) -> dict[int, list[tsm_types.Topic]]:
    """The topics data published on each topic of ``system`` reaches (itself first), by
    the routes of :class:`FlowTable`: what a publisher bound to the topic would feed."""
    T = tsm()
    edges, _ = _connections(system)
    return {
        id(topic): _Walk(topic, edges, T).order
        for container in system.containers
        for topic in container.topics
    }


def _connections(system: tsm_types.System) -> tuple[Edges, Callers]:
    """The endpoint connections of ``system``: topic to topic, and stand-in server to
    the connections taking its calls on."""
    edges: Edges = defaultdict(list)  # topic -> (conn, topic)
    callers: Callers = defaultdict(list)  # stand-in server -> connections
    for connection in system.connections:
        source, target = connection.source, connection.target
        taking, giving = kind_of(source), kind_of(target)
        if taking.subscribes and giving.publishes:
            source_topic, target_topic = bound_topic(source), bound_topic(target)
            if source_topic is not None and target_topic is not None:
                edges[id(source_topic)].append((connection, target_topic))
        elif taking.serves and giving.calls:
            callers[id(source)].append(connection)
    return edges, callers


def _answering(
    server: tsm_types.ServiceServer | None, callers: Callers, T: tsm_types.Metamodel
) -> tuple[tsm_types.ServiceServer | None, Route]:
    """The node server behind a chain of endpoint stand-ins and the connections the calls
    cross; ``(None, ())`` when the chain ends without one (or its node was pruned)."""
    route: list[tsm_types.EndpointConnection] = []
    seen: set[int] = set()
    while server is not None and not isinstance(server.eContainer(), T.Node):
        if id(server) in seen or not callers.get(id(server)):
            return None, ()
        seen.add(id(server))
        connection = callers[id(server)][0]
        route.append(connection)
        server = cast("tsm_types.ServiceClient", connection.target).server
    if server is None or server.eContainer().eContainer() is None:
        return None, ()
    return server, tuple(route)


class _Walk:
    """The topics data published on ``start`` reaches, in the order they are found (the
    order every earlier consumer of the routes used), the first route to each, and how
    many routes reach each (counted up to 2 over the routes that revisit no topic)."""

    def __init__(self, start: tsm_types.Topic, edges: Edges, T: tsm_types.Metamodel) -> None:
        home = start.eContainer()
        robot = T.RobotContainer
        # topic -> (connection, previous topic)
        self.parent: dict[int, tuple[tsm_types.EndpointConnection, tsm_types.Topic] | None] = {
            id(start): None
        }
        found = {id(start): start}
        frontier = [start]
        beyond: dict[int, Reached] = {}  # topic reached only through a robot relay
        self.relaying: set[int] = set()  # reached topics whose container passes data on
        while frontier:
            topic = frontier.pop()
            container = topic.eContainer()
            relays = not (isinstance(container, robot) and container is not home)
            if relays:
                self.relaying.add(id(topic))
            for connection, target in edges.get(id(topic), ()):
                if id(target) in found:
                    continue
                if not relays:
                    beyond.setdefault(id(target), (target, cast("tsm_types.Container", container)))
                    continue
                found[id(target)] = target
                self.parent[id(target)] = (connection, topic)
                frontier.append(target)
        self.order = list(found.values())
        self.beyond = self._unreached(beyond, found, edges)
        self._counts = self._count_routes(start, found, edges)

    @staticmethod
    def _unreached(
        beyond: dict[int, Reached], found: dict[int, tsm_types.Topic], edges: Edges
    ) -> list[Reached]:
        """The topics only a robot relay would reach, each with the first such robot."""
        cut: dict[int, Reached] = {}
        frontier = [pair for key, pair in beyond.items() if key not in found]
        for topic, robot in frontier:
            cut.setdefault(id(topic), (topic, robot))
        while frontier:
            topic, robot = frontier.pop()
            for _, target in edges.get(id(topic), ()):
                if id(target) not in found and id(target) not in cut:
                    cut[id(target)] = (target, robot)
                    frontier.append((target, robot))
        return list(cut.values())

    def route(self, topic: tsm_types.Topic) -> Route:
        hops = []
        step = self.parent[id(topic)]
        while step is not None:
            connection, previous = step
            hops.append(connection)
            step = self.parent[id(previous)]
        return tuple(reversed(hops))

    def count(self, topic: tsm_types.Topic) -> int:
        return self._counts.get(id(topic), 1)

    def _count_routes(
        self, start: tsm_types.Topic, found: dict[int, tsm_types.Topic], edges: Edges
    ) -> dict[int, int]:
        """Routes from ``start`` to each reached topic over the edges the walk took (between
        reached topics, leaving a relaying container), capped at 2. An edge back to a
        topic on the current depth-first path closes a loop and is no route."""
        inside = {
            key: [t for _, t in edges.get(key, ()) if id(t) in found and id(t) != id(start)]
            for key in self.relaying
        }
        # depth-first order without the edges that close loops, then count in that order
        order: list[int] = []
        state: dict[int, int] = {}  # 1 on the path, 2 done
        keep: dict[int, list[int]] = defaultdict(list)
        stack: list[tuple[int, Iterator[tsm_types.Topic]]] = [
            (id(start), iter(inside.get(id(start), ())))
        ]
        state[id(start)] = 1
        while stack:
            key, targets = stack[-1]
            target = next(targets, None)
            if target is None:
                stack.pop()
                state[key] = 2
                order.append(key)
                continue
            if state.get(id(target)) == 1:
                continue  # closes a loop
            keep[id(target)].append(key)
            if id(target) not in state:
                state[id(target)] = 1
                stack.append((id(target), iter(inside.get(id(target), ()))))
        counts = {id(start): 1}
        for key in reversed(order):  # a topic after every topic with an edge into it
            if key != id(start):
                counts[key] = min(2, sum(counts.get(k, 0) for k in keep[key]))
        return counts
