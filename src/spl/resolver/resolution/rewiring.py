"""Endpoint rewiring after node migration (docs/resolution.md), minimal by construction.

Rather than patching bridges migration by migration, the wiring across containers is
derived once from the data flows of the template:

1. The template's flow table (:mod:`spl.resolver.architecture.flows`, the rules every output
   follows) says which publisher feeds which subscriber, and which real server behind
   any chain of stand-ins answers each client.
2. Each node interface is bound to a topic of the container its node now lives in:
   its own topic if it stayed; else the topic its flow peers there use, or a topic of
   the target container with the same ROS name and type (reused when it exists,
   created otherwise).
3. For every flow whose two ends now live in different containers, one bridge between
   their topics, unless other bridges already carry its data there (no message arrives
   twice) or it would close a loop; for every client whose server lives elsewhere, one
   service bridge. Flows inside one container need nothing.

So there is never a bridge inside one container, never a hairpin (a node that moved
next to its peer is wired to it locally and the bridge that served it disappears),
never a duplicate bridge for a topic several migrated nodes share, and same-named
topics are reused. The result is the same whatever order migrations ran in, and the
resolved model, resolved again, is itself. Flows that no wiring obeying these rules
can deliver are reported: SPL031 (peers in one container on two topics) and SPL032
(a bridge that would close a loop).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

import networkx as nx

from spl.core.diagnostics import Diagnostic, location_of
from spl.metamodels import tsm
from spl.metamodels.interface_kinds import kind_of
from spl.resolver.architecture import endpoints
from spl.resolver.architecture.flows import (
    CutRoute,
    FlowTable,
    NodeInterfaces,
    topic_of,
)
from spl.resolver.resolution.context import Cause, qualified
from spl.resolver.resolution.trace import Trace

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

    Bound = tsm_types.Publisher | tsm_types.Subscriber  # a node interface bound to a topic
    TopicFlow = tuple[tsm_types.Publisher, tsm_types.Subscriber]
    # (id(source topic), id(target topic)) -> the flows a bridge between them carries
    Bridges = dict[tuple[int, int], list[TopicFlow]]


class Causes:
    """Why interfaces left the container of their template flows: the resolution
    statements that migrated their node or connected them to a topic of another
    container (``ResolutionContext.displaced``), so every rewiring decision in the trace
    names the element and feature behind it."""

    def __init__(self, displaced: dict[int, Cause]) -> None:
        self.displaced = displaced

    def of(self, *interfaces: tsm_types.Interface) -> Cause | None:
        """The first cause among ``interfaces`` (their own, else their node's)."""
        for interface in interfaces:
            for element in (interface, interface.eContainer()):
                if id(element) in self.displaced:
                    return self.displaced[id(element)]
        return None

    def record(
        self, trace: Trace, subject: str, decision: str, text: str, *interfaces: tsm_types.Interface
    ) -> None:
        """A trace entry ``text``, with the cause among ``interfaces`` and its location."""
        cause = self.of(*interfaces)
        if cause is None:
            trace.record(subject, decision, text)
        else:
            trace.record(subject, decision, f"{text}, as {cause.text}", cause.location)


def rewire(
    system: tsm_types.System, trace: Trace, displaced: dict[int, Cause]
) -> tuple[list[Diagnostic], tuple[CutRoute, ...]]:
    """Rebuild the cross-container wiring; ``displaced`` says why interfaces left the
    container of their template flows (ResolutionContext.displaced). Returns the
    warnings, and the template's routes a robot relay would have needed (the bridges of
    which it drops), for the architecture checks to say why a subscriber is unfed."""
    causes = Causes(displaced)
    template = FlowTable.of(system)  # interfaces still point at their template topics
    local_before = {  # clients bound to their server itself, not to a stand-in
        id(f.source)
        for f in template
        if not f.kind.on_topic and kind_of(f.source).bound_to(f.source) is f.target
    }
    publishers, subscribers, clients = NodeInterfaces.of(system.containers)
    bound: list[Bound] = [*publishers, *subscribers]
    order = {id(i): n for n, i in enumerate(bound)}
    served_by = {
        id(f.source): cast("tsm_types.ServiceServer", f.target)
        for f in template
        if not f.kind.on_topic
    }
    flows = [cast("TopicFlow", (f.source, f.target)) for f in template if f.kind.on_topic]
    flows.sort(key=lambda flow: (order[id(flow[0])], order[id(flow[1])]))
    _bind_moved(bound, flows, trace, causes)

    bridges: Bridges = {}
    warnings: list[Diagnostic] = []
    for publisher, subscriber in flows:
        if _container(publisher) is not _container(subscriber):
            bridges.setdefault((id(publisher.topic), id(subscriber.topic)), []).append(
                (publisher, subscriber)
            )
        elif publisher.topic is not subscriber.topic:
            warnings.append(
                Diagnostic(
                    location_of(subscriber),
                    f"{qualified(subscriber)} was fed by {qualified(publisher)} through "
                    f"another container; both now live in {_container(publisher).name} "
                    f"on different topics ({qualified(topic_of(publisher))}, "
                    f"{qualified(topic_of(subscriber))}): connect them to one topic",
                    "warning",
                    "SPL031",
                )
            )

    for container in system.containers:
        container.endpoint.interfaces.clear()
    system.connections.clear()
    wiring = endpoints.EndpointWiring(system)
    # built in the order of the topics they join, which the printed model keeps: so the
    # resolved model, resolved again, gives the same bridges in the same order
    position = {
        id(t): (i, j) for i, c in enumerate(system.containers) for j, t in enumerate(c.topics)
    }
    minimal = _minimal_bridges(bridges, trace, warnings)
    for key in sorted(minimal, key=lambda k: (position[k[0]], position[k[1]])):
        shared = minimal[key]
        publisher, subscriber = shared[0]
        wiring.topic_bridge(topic_of(publisher), topic_of(subscriber))
        ends = [end for flow in shared for end in flow]
        if causes.of(*ends) is not None:
            carried = ", ".join(f"{qualified(p)} -> {qualified(s)}" for p, s in shared)
            causes.record(
                trace,
                qualified(topic_of(publisher)),
                "bridged",
                f"to {qualified(topic_of(subscriber))} through the endpoints, carrying {carried}",
                *ends,
            )
    for client in clients:
        server = served_by.get(id(client))
        if server is None:
            client.server = None
        elif _container(server) is _container(client):
            if client.server is not server:  # most are bound so already: pyecore notifies
                client.server = server
            if id(client) not in local_before:
                causes.record(
                    trace,
                    qualified(client),
                    "rebound",
                    f"to {qualified(server)}, served in its own container "
                    f"{_container(client).name} now (the template reached it through the "
                    "endpoints)",
                    client,
                    server,
                )
        else:
            wiring.service_bridge(client, server)
            if causes.of(client, server) is not None:
                causes.record(
                    trace,
                    qualified(client),
                    "bridged",
                    f"to {qualified(server)} in {_container(server).name} through an endpoint "
                    f"stand-in in {_container(client).name}",
                    client,
                    server,
                )
    return warnings, template.cut


def _container(interface: tsm_types.Interface) -> tsm_types.Container:
    return interface.eContainer().eContainer()


def _minimal_bridges(bridges: Bridges, trace: Trace, warnings: list[Diagnostic]) -> Bridges:
    """The bridges to build: no loop, and none that a chain of others makes redundant.

    Bridges are taken in flow order; one that would close a loop (data bridged from a
    topic back into it, as when a moved node both publishes and subscribes a topic whose
    other ends stayed behind) is left out, since every message would circle for ever,
    and each flow that then cannot be delivered is reported (SPL032). Of the rest, a
    bridge A.T -> C.T whose data already travels A.T -> B.T -> C.T is dropped (the
    transitive reduction), or every message would reach C twice.
    """
    graph = nx.DiGraph()
    looping = []
    for key in bridges:
        if key[0] in graph and key[1] in graph and nx.has_path(graph, key[1], key[0]):
            looping.append(key)
        else:
            graph.add_edge(*key)
    for key in looping:
        for publisher, subscriber in bridges[key]:
            if not nx.has_path(graph, *key):
                warnings.append(
                    Diagnostic(
                        location_of(subscriber),
                        f"{qualified(subscriber)} is no longer fed by {qualified(publisher)}: "
                        f"bridging {qualified(topic_of(publisher))} to "
                        f"{qualified(topic_of(subscriber))} would send data round a loop of "
                        "bridges back to where it came from",
                        "warning",
                        "SPL032",
                    )
                )
    kept = nx.transitive_reduction(graph)
    for (source, target), flows in bridges.items():
        if (source, target) not in looping and not kept.has_edge(source, target):
            publisher, subscriber = flows[0]
            trace.record(
                qualified(topic_of(publisher)),
                "not bridged",
                f"to {qualified(topic_of(subscriber))} directly: its data already arrives there "
                "through other bridges",
            )
    return {key: flows for key, flows in bridges.items() if kept.has_edge(*key)}


def _bind_moved(
    interfaces: list[Bound], flows: list[TopicFlow], trace: Trace, causes: Causes
) -> None:
    """Bind each interface of a migrated node (or one connected to a topic of another
    container) to a topic of its own container.

    Interfaces that now share a container and were linked by a template flow must share
    one topic there, or the flow would need a bridge inside the container. Such a group
    joins the topic its unmoved members use; when none stayed, its first moved member's
    topic (same ROS name and type, reused or created) is shared by all. When the unmoved
    members use two topics, no single topic serves them all: each moved interface keeps
    the ROS-name rule and the flows that cannot be delivered are reported (SPL031).
    """
    moved = [i for i in interfaces if topic_of(i).eContainer() is not _container(i)]
    if not moved:
        return
    position = {id(i): n for n, i in enumerate(interfaces)}
    peers = nx.Graph()
    peers.add_nodes_from(id(i) for i in moved)
    for publisher, subscriber in flows:
        if _container(publisher) is _container(subscriber):
            peers.add_edge(id(publisher), id(subscriber))
    by_id = {id(i): i for i in interfaces}
    moved_ids = {id(i) for i in moved}
    indexes: dict[int, TopicIndex] = {}
    for first in moved:
        if topic_of(first).eContainer() is _container(first):
            continue  # bound with an earlier member of its group
        group = sorted(nx.node_connected_component(peers, id(first)), key=position.__getitem__)
        members = [by_id[k] for k in group]
        fixed = list(dict.fromkeys(topic_of(m) for m in members if id(m) not in moved_ids))
        container = _container(first)
        if id(container) not in indexes:
            indexes[id(container)] = TopicIndex(container, causes)
        index = indexes[id(container)]
        if len(fixed) > 1:
            for member in members:
                if id(member) in moved_ids:
                    member.topic = index.local_topic(member, trace)
            continue
        if fixed:
            topic = fixed[0]
        else:
            topic = first.topic = index.local_topic(first, trace)
        for member in members:
            if id(member) in moved_ids and member.topic is not topic:
                causes.record(
                    trace,
                    qualified(member),
                    "rewired",
                    f"to {qualified(topic)}, the topic of the interfaces it exchanged data "
                    f"with in the template, which now live in {container.name} too",
                    member,
                )
                member.topic = topic


class TopicIndex:
    """The topics of one container by (ROS name, type) and by name, kept up to date."""

    def __init__(self, container: tsm_types.Container, causes: Causes) -> None:
        self.container = container
        self.causes = causes
        self.by_ros_name = {(t.rosName, t.type): t for t in container.topics}
        self.names = {t.name for t in container.topics}

    def local_topic(self, interface: Bound, trace: Trace) -> tsm_types.Topic:
        """The topic standing for ``interface``'s template topic: reused when one with
        the same ROS name and type exists, created otherwise (and shared from then on)."""
        template = topic_of(interface)
        topic = self.by_ros_name.get((template.rosName, template.type))
        if topic is not None:
            self.causes.record(
                trace,
                qualified(interface),
                "rewired",
                f"to {qualified(topic)} (reused: same ROS name {topic.rosName} and type "
                f"as {qualified(template)})",
                interface,
            )
            return topic
        name, suffix = template.name, 1
        while name in self.names:
            suffix += 1
            name = f"{template.name}_{suffix}"
        topic = tsm().Topic(name=name, type=template.type, rosName=template.rosName)
        topic.srcFile, topic.srcLine, topic.srcCol = (
            template.srcFile,
            template.srcLine,
            template.srcCol,
        )
        self.container.topics.append(topic)
        self.by_ros_name[(topic.rosName, topic.type)] = topic
        self.names.add(name)
        self.causes.record(
            trace,
            qualified(topic),
            "created",
            f"in {self.container.name} for {qualified(interface)}, mirroring "
            f"{qualified(template)} (ROS name {template.rosName})",
            interface,
        )
        return topic
