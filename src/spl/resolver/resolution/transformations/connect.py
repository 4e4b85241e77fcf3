"""What the four connection kinds of the mapping paper (docs/index.md) share: interface to
an existing topic
(:mod:`.to_topic`), interface to a new topic (:mod:`.new_topic`), service client to
server (:mod:`.to_server`), and a bridge between containers (:mod:`.bridge`).

The .rm builder resolved nodes and interfaces against the template; topics and
containers are looked up here, in the product as the statements before left it
(docs/semantics.md): a node is where earlier migrations put it, and a topic an earlier
`new topic` created exists.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Location, location_of
from spl.dsl.rm.messages import agree, missing_topic
from spl.resolver.architecture.flows import node_of  # the .rm names node interfaces only
from spl.resolver.resolution.context import Cause, ResolutionContext, qualified
from spl.resolver.resolution.transformations.kind import Decision, DecisionKey, Predictions

if TYPE_CHECKING:
    from spl.dsl.rm.names import Names
    from spl.metamodels import rm_types, tsm_types

    Connect = rm_types.ConnectToTopic | rm_types.ConnectToNewTopic
    Served = rm_types.ConnectService | rm_types.ConnectBridge


def here(interface: tsm_types.Interface) -> tsm_types.Container:
    """The container an interface's node is in now (after the migrations so far)."""
    return interface.eContainer().eContainer()


def type_mismatch(
    ctx: ResolutionContext,
    a: tsm_types.Interface | tsm_types.Topic,
    b: tsm_types.Topic,
    where: Location | None,
) -> bool:
    if agree(a, b):
        return False
    ctx.sink.error(where, f"type mismatch: {a.name} is {a.type}, {b.name} is {b.type}")
    return True


def connect_interface(
    interface: tsm_types.Interface,
    topic: tsm_types.Topic,
    ctx: ResolutionContext,
    where: Location | None,
) -> None:
    """Bind ``interface`` to ``topic``; one of another container is carried by the
    endpoints, and the rewiring names this statement as the cause."""
    node = node_of(interface)
    ctx.keep(node, f"its interface {interface.name} is connected by {ctx.by()}", where)
    ctx.keep(topic, f"{interface.name} of {node.name} is connected to it by {ctx.by()}", where)
    if ctx.decide("topic", interface, qualified(topic), where):
        cast("tsm_types.Publisher | tsm_types.Subscriber", interface).topic = topic
        owner = cast("tsm_types.Container", topic.eContainer())  # a topic of the product
        if owner is not here(interface):  # the endpoints will carry it
            ctx.displaced[id(interface)] = Cause(
                f"{qualified(interface)} is connected to {qualified(topic)} of container "
                f"{owner.name} by {ctx.by()}",
                where,
            )
        ctx.trace.record(
            qualified(interface), "connected", f"to topic {qualified(topic)} by {ctx.by()}", where
        )


def topic_named(
    ctx: ResolutionContext,
    reference: rm_types.TopicReference,
    node: tsm_types.Node | None,
    where: Location | None,
) -> tsm_types.Topic | None:
    """The topic a reference names now: in its container, else where ``node`` is."""
    if reference.container is not None:
        container = ctx.copy_of(reference.container)
        topic = ctx.topic_named(container, reference.name)
        if topic is None:
            ctx.sink.error(where, f"unknown topic {reference.name} in container {container.name}")
        return topic
    node = cast("tsm_types.Node", node)  # a reference without container is a node's
    topic = ctx.topic_named(node.eContainer(), reference.name)
    if topic is None:
        message = missing_topic(reference.name, node, [node.eContainer()])
        ctx.sink.error(where, f"{message}, where {node.name} is at this point")
    return topic


def topic_decision(
    t: Connect, element: rm_types.ResolutionElement, names: Names
) -> Iterator[tuple[DecisionKey, Decision]]:
    """A `to topic` or `to new topic` decides its interface's topic, identified by its
    container and name (a `new topic` declared by two elements is one topic)."""
    container: tsm_types.Container | None = getattr(t.topic, "container", None)
    places = names.places(node_of(t.interface))
    if container is None and len(places) == 1:
        container = places[0]
    name = t.topic.name
    value = f"{container.name}.{name}" if container is not None else name
    topic = (container.name if container is not None else None, name)
    decision = Decision("topic", qualified(t.interface), value, element, location_of(t), topic)
    yield ("topic", id(t.interface)), decision


def predict_topic(t: Connect, element: rm_types.ResolutionElement, effects: Predictions) -> None:
    node, aspect = node_of(t.interface), f"topic of {t.interface.name}"
    effects.effect(node, aspect, element, effects.topic_value(t), location_of(t))


def server_decision(
    t: Served, element: rm_types.ResolutionElement
) -> Iterator[tuple[DecisionKey, Decision]]:
    """A `to server` or service bridge decides its client's server."""
    server = cast("tsm_types.ServiceServer", t.server)  # a service bridge's is set
    value = f"{server.eContainer().eContainer().name}.{qualified(server)}"
    client = cast("tsm_types.ServiceClient", t.client)
    decision = Decision("server", qualified(client), value, element, location_of(t))
    yield ("server", id(t.client)), decision
