"""The invariants of docs/resolution.md checked on a resolved architecture, independently of the
engine: what the template promises is computed from the test's own record of it
(:mod:`random_lines`), and what the product delivers from the resolved pyecore model
with a graph built here, not with the engine's rewiring code."""

from __future__ import annotations

from collections import Counter
from typing import Any

import networkx as nx

from support.random_lines import Element, LineSpec

Endpoint = tuple[str, str]  # (node, interface)


# -- what the template promises ----------------------------------------------------------
def active_elements(spec: LineSpec, selected: set[str]) -> list[Element]:
    return [e for e in spec.elements if (e.feature in selected) != e.negated]


def placement(spec: LineSpec, selected: set[str]) -> dict[str, str]:
    """Node -> container of every node the product keeps (docs/resolution.md, steps 4 and 7)."""
    active = active_elements(spec, selected)
    kept = {n for e in active for n in e.requires} | {n for e in active for n, _ in e.migrations}
    moved = {n: target for e in active for n, target in e.migrations}
    return {
        n.name: moved.get(n.name, n.container)
        for n in spec.nodes
        if not n.optional or n.name in kept
    }


def template_flows(spec: LineSpec) -> set[tuple[Endpoint, Endpoint]]:
    """(publisher, subscriber) pairs of the template: the subscriber's topic is the
    publisher's, or reachable from it through bridges."""
    graph = nx.DiGraph()
    graph.add_nodes_from((t.container, t.name) for t in spec.topics)
    graph.add_edges_from(spec.topic_bridges)
    ends: dict[str, list[tuple[tuple[str, str], Endpoint]]] = {"publishes": [], "subscribes": []}
    for node in spec.nodes:
        for i in node.interfaces:
            if i.kind in ends:
                ends[i.kind].append(((node.container, i.topic), (node.name, i.name)))
    return {
        (publisher, subscriber)
        for source, publisher in ends["publishes"]
        for target, subscriber in ends["subscribes"]
        if target == source or nx.has_path(graph, source, target)
    }


def _topics_of(spec: LineSpec) -> dict[Endpoint, tuple[str, str]]:
    """(container, topic) of each bound interface of the template."""
    return {
        (node.name, i.name): (node.container, i.topic)
        for node in spec.nodes
        for i in node.interfaces
        if i.topic is not None
    }


def relayed_flows(spec: LineSpec) -> set[tuple[Endpoint, Endpoint]]:
    """The template flows that only reach their subscriber through another robot: data
    that reaches a robot container's topic from elsewhere goes no further
    (docs/semantics.md F3), so the product may cut them."""
    graph = nx.DiGraph(spec.topic_bridges)
    topic_of = _topics_of(spec)
    relayed = set()
    for publisher, subscriber in template_flows(spec):
        source, target = topic_of[publisher], topic_of[subscriber]
        reached, frontier = {source}, [source]
        while frontier:  # a robot's topic reached from elsewhere passes nothing on
            topic = frontier.pop()
            if topic != source and spec.containers[topic[0]] == "robot":
                continue
            for onward in graph.successors(topic) if topic in graph else ():
                if onward not in reached:
                    reached.add(onward)
                    frontier.append(onward)
        if target not in reached:
            relayed.add((publisher, subscriber))
    return relayed


def template_calls(spec: LineSpec) -> dict[Endpoint, Endpoint]:
    """Client -> the server it calls, directly or through a service bridge."""
    calls = {
        (node.name, i.name): i.server
        for node in spec.nodes
        for i in node.interfaces
        if i.kind == "calls" and i.server is not None
    }
    for (_, node, client), (_, server_node, server) in spec.service_bridges:
        calls[(node, client)] = (server_node, server)
    return calls


# -- what the product delivers -----------------------------------------------------------
def _container(element: Any) -> Any:
    """The container of a node interface, an endpoint interface or a topic."""
    while element.eClass.name not in ("RobotContainer", "CloudContainer"):
        element = element.eContainer()
    return element


def _interfaces(system: Any) -> dict[Endpoint, Any]:
    return {
        (node.name, i.name): i
        for c in system.containers
        for node in c.nodes
        for i in node.interfaces
    }


def undeliverable(spec: LineSpec, selected: set[str]) -> set[tuple[Endpoint, Endpoint]]:
    """Flows no rewiring can deliver: interfaces that end up in one container and are
    linked by template flows must share one topic there (a bridge inside a container is
    forbidden), which is impossible when their unmoved members already use two topics."""
    where = placement(spec, selected)
    moved = {n for e in active_elements(spec, selected) for n, _ in e.migrations}
    topic_of = _topics_of(spec)
    local = [
        (p, s)
        for p, s in template_flows(spec)
        if p[0] in where and s[0] in where and where[p[0]] == where[s[0]]
    ]
    groups = nx.Graph(local)
    blocked = set()
    for group in nx.connected_components(groups):
        fixed = {topic_of[member] for member in group if member[0] not in moved}
        if len(fixed) > 1:
            blocked |= {(p, s) for p, s in local if p in group}
    return blocked


def check_resolved(spec: LineSpec, selected: set[str], system: Any, warnings=()) -> None:
    """Assert every invariant of docs/resolution.md on ``system``, the product of ``selected``;
    ``warnings`` are the engine's, which must name every flow it could not deliver."""
    where = placement(spec, selected)
    actual = {n.name: c.name for c in system.containers for n in c.nodes}
    assert actual == where, f"node placement {actual}, expected {where}"
    interfaces = _interfaces(system)

    # everything an interface is bound to lies in its own container
    for (node, name), i in interfaces.items():
        bound = getattr(i, "topic", None) or getattr(i, "server", None)
        if bound is not None:
            assert _container(bound) is _container(i), f"{node}.{name} bound across containers"
    for container in system.containers:
        for i in container.endpoint.interfaces:
            bound = getattr(i, "topic", None)
            if bound is not None:
                assert _container(bound) is container, f"endpoint {i.name} bound elsewhere"

    # bridges: between two containers, once per pair, never back into a container
    pairs = Counter((id(c.source), id(c.target)) for c in system.connections)
    assert max(pairs.values(), default=1) == 1, "two bridges for one (source, target) pair"
    topic_pairs = Counter(
        (id(c.source.topic), id(c.target.topic))
        for c in system.connections
        if c.source.eClass.name == "Subscriber"
    )
    assert max(topic_pairs.values(), default=1) == 1, "two bridges between one pair of topics"
    data = nx.DiGraph()
    for connection in system.connections:
        source, target = connection.source, connection.target
        assert _container(source) is not _container(target), "bridge within one container"
        if source.eClass.name == "Subscriber":
            assert target.eClass.name == "Publisher", "topic bridge to a non-publisher"
            data.add_edge(id(source.topic), id(target.topic))
    containers = {id(t): _container(t).name for c in system.containers for t in c.topics}
    assert nx.is_directed_acyclic_graph(data), "data can travel round a cycle of bridges"
    for x, y in data.edges:  # each message arrives once: no bridge duplicates a chain
        others = data.copy()
        others.remove_edge(x, y)
        assert not nx.has_path(others, x, y), (
            f"bridge {containers[x]} -> {containers[y]} duplicates a chain of bridges"
        )

    # every template flow between kept nodes is still delivered, or it cannot be and the
    # engine says so
    blocked = undeliverable(spec, selected)
    relayed = relayed_flows(spec)
    fed: set[Endpoint] = set()  # subscribers some template flow still reaches
    cut: list[Endpoint] = []  # subscribers of flows cut where another robot would relay
    reported = {str(w) for w in warnings if w.code == "SPL031"}
    looping = {str(w) for w in warnings if w.code == "SPL032"}
    carried: set[tuple[int, int]] = set()  # (publisher topic, subscriber topic) of flows
    for publisher, subscriber in sorted(template_flows(spec)):
        if publisher[0] not in where or subscriber[0] not in where:
            continue
        source, target = interfaces[publisher].topic, interfaces[subscriber].topic
        assert source is not None and target is not None, f"{publisher} -> {subscriber} unbound"
        delivered = source is target or (
            id(source) in data and id(target) in data and nx.has_path(data, id(source), id(target))
        )
        if delivered:
            fed.add(subscriber)
        elif (publisher, subscriber) in relayed:
            cut.append(subscriber)
            continue
        if (publisher, subscriber) in blocked and not delivered:
            names = (".".join(subscriber) + " was fed by " + ".".join(publisher)).split()
            assert any(all(n in w for n in names) for w in reported), (
                f"flow {publisher} -> {subscriber} lost without a warning"
            )
            continue
        if not delivered and id(target) in data and id(source) in data:
            # allowed only when bridging it would close a loop, and the engine says so
            names = (".".join(subscriber) + " is no longer fed by " + ".".join(publisher)).split()
            assert nx.has_path(data, id(target), id(source)), (
                f"flow {publisher} -> {subscriber} is no longer delivered"
            )
            assert any(all(n in w for n in names) for w in looping), (
                f"flow {publisher} -> {subscriber} lost to a loop without a warning"
            )
            continue
        assert delivered, f"flow {publisher} -> {subscriber} is no longer delivered"
        if source is not target:  # no hairpin: some route never re-enters a container
            routes = nx.all_simple_paths(data, id(source), id(target))
            assert any(len({containers[t] for t in r}) == len(r) for r in routes), (
                f"hairpin: every route of {publisher} -> {subscriber} re-enters a container"
            )
            carried.add((id(source), id(target)))

    # a subscriber that only another robot's relay fed is unfed, and the engine says why
    unfed = [str(w) for w in warnings if w.code == "SPL045"]
    for subscriber in set(cut) - fed:
        said = [w for w in unfed if f"{'.'.join(subscriber)} subscribes" in w]
        assert any("a robot passes on no data but its own" in w for w in said), (
            f"{subscriber} is fed only through another robot, and no SPL045 says so"
        )

    # minimal: every bridge lies on the way of some flow of the template
    def reaches(a: int, b: int) -> bool:
        return a == b or nx.has_path(data, a, b)

    for x, y in data.edges:
        assert any(reaches(s, x) and reaches(y, t) for s, t in carried), (
            f"bridge {containers[x]} -> {containers[y]} carries no flow of the template"
        )

    # every client still reaches its server
    for client, server in sorted(template_calls(spec).items()):
        if client[0] not in where or server[0] not in where:
            continue
        reached = _serving(system, interfaces[client].server)
        assert reached is interfaces[server], f"client {client} does not reach {server}"

    # every interface of a migrated node is wired like the template wired it
    for element in active_elements(spec, selected):
        for node, _ in element.migrations:
            for i in spec.node(node).interfaces:
                bound = interfaces[(node, i.name)]
                if i.kind in ("publishes", "subscribes"):
                    assert bound.topic is not None, f"{node}.{i.name} lost its topic"


def _serving(system: Any, server: Any) -> Any:
    """The node server behind ``server``, following endpoint stand-ins across bridges."""
    seen = set()
    while server is not None and server.eContainer().eClass.name == "Endpoint":
        assert id(server) not in seen, "a cycle of service stand-ins"
        seen.add(id(server))
        callers = [c.target for c in system.connections if c.source is server]
        assert len(callers) == 1, f"stand-in {server.name} has {len(callers)} connections"
        server = callers[0].server
    return server
