"""Connection transformations: the four kinds of seeds/003.

Interface to an existing topic, interface to a new topic, service client to server,
and a bridge between containers. The .rm builder resolved nodes and interfaces against
the template; topics and containers are looked up here, in the product as the
statements before left it (docs/semantics.md): a node is where earlier migrations put
it, and a topic an earlier `new topic` created exists.
"""

from __future__ import annotations

from typing import Any

from spl.diagnostics import location_of
from spl.dsl.rm_names import (
    agree,
    missing_topic,
    new_topic_clash,
    not_served_here,
    same_container_bridge,
    same_topic,
)
from spl.resolver.context import Cause, ResolutionContext, qualified


def _here(interface: Any) -> Any:
    """The container an interface's node is in now (after the migrations so far)."""
    return interface.eContainer().eContainer()


def _type_mismatch(ctx: ResolutionContext, a: Any, b: Any, where: Any) -> bool:
    if agree(a, b):
        return False
    ctx.sink.error(where, f"type mismatch: {a.name} is {a.type}, {b.name} is {b.type}")
    return True


def _connect_interface(interface: Any, topic: Any, ctx: ResolutionContext, where: Any) -> None:
    node = interface.eContainer()
    ctx.keep(node, f"its interface {interface.name} is connected by {ctx.by()}", where)
    ctx.keep(topic, f"{interface.name} of {node.name} is connected to it by {ctx.by()}", where)
    if ctx.decide("topic", interface, qualified(topic), where):
        interface.topic = topic
        if topic.eContainer() is not _here(interface):  # the endpoints will carry it
            ctx.displaced[id(interface)] = Cause(
                f"{qualified(interface)} is connected to {qualified(topic)} of container "
                f"{topic.eContainer().name} by {ctx.by()}",
                where,
            )
        ctx.trace.record(
            qualified(interface), "connected", f"to topic {qualified(topic)} by {ctx.by()}", where
        )


def _topic(ctx: ResolutionContext, reference: Any, node: Any, where: Any) -> Any:
    """The topic a reference names now: in its container, else where ``node`` is."""
    if reference.container is not None:
        container = ctx.copy_of(reference.container)
        topic = ctx.topic_named(container, reference.name)
        if topic is None:
            ctx.sink.error(where, f"unknown topic {reference.name} in container {container.name}")
        return topic
    topic = ctx.topic_named(node.eContainer(), reference.name)
    if topic is None:
        message = missing_topic(reference.name, node, [node.eContainer()])
        ctx.sink.error(where, f"{message}, where {node.name} is at this point")
    return topic


def to_topic(transformation: Any, ctx: ResolutionContext) -> None:
    where = location_of(transformation)
    interface = ctx.copy_of(transformation.interface)
    topic = _topic(ctx, transformation.topic, interface.eContainer(), where)
    if topic is None or _type_mismatch(ctx, interface, topic, where):
        return
    _connect_interface(interface, topic, ctx, where)


def to_new_topic(transformation: Any, ctx: ResolutionContext) -> None:
    """Creates the topic where the interface's node is now; a topic of that name already
    there is only accepted when an earlier `new topic` made it alike."""
    where = location_of(transformation)
    interface = ctx.copy_of(transformation.interface)
    declaration = transformation.topic
    container = _here(interface)
    topic = ctx.topic_named(container, declaration.name)
    if topic is None:
        topic = ctx.create_topic(container, declaration)
    elif not (ctx.is_created(topic) and same_topic(topic, declaration)):
        clash = new_topic_clash(declaration.name, container, topic, ctx.is_created(topic))
        ctx.sink.error(where, clash)
        return
    _connect_interface(interface, topic, ctx, where)


def to_server(transformation: Any, ctx: ResolutionContext) -> None:
    client = ctx.copy_of(transformation.client)
    server = ctx.copy_of(transformation.server)
    where = location_of(transformation)
    if _here(client) is not _here(server):
        message = not_served_here(
            transformation.client, transformation.server, [_here(server)], [_here(client)]
        )
        ctx.sink.error(where, f"{message} (containers at this point)")
        return
    ctx.keep(client.eContainer(), f"its client {client.name} is connected by {ctx.by()}", where)
    ctx.keep(server.eContainer(), f"its server {server.name} is connected by {ctx.by()}", where)
    if ctx.decide("server", client, qualified(server), where):
        client.server = server
        ctx.trace.record(
            qualified(client), "connected", f"to server {qualified(server)} by {ctx.by()}", where
        )


def bridge(transformation: Any, ctx: ResolutionContext) -> None:
    where = location_of(transformation)
    if transformation.sourceTopic is not None:
        source = _topic(ctx, transformation.sourceTopic, None, where)
        target = _topic(ctx, transformation.targetTopic, None, where)
        if source is None or target is None or _type_mismatch(ctx, source, target, where):
            return
        ctx.wiring.topic_bridge(source, target)
        for topic in (source, target):
            ctx.keep(topic, f"bridged by {ctx.by()}", where)
        ctx.trace.record(
            qualified(source), "bridged", f"to {qualified(target)} by {ctx.by()}", where
        )
        return
    client = ctx.copy_of(transformation.client)
    server = ctx.copy_of(transformation.server)
    if _here(client) is _here(server):
        ctx.sink.error(where, same_container_bridge(client, server, _here(client)))
        return
    ctx.keep(client.eContainer(), f"its client {client.name} is bridged by {ctx.by()}", where)
    ctx.keep(server.eContainer(), f"its server {server.name} is bridged by {ctx.by()}", where)
    if ctx.decide("server", client, qualified(server), where):
        ctx.wiring.service_bridge(client, server)
        ctx.trace.record(
            qualified(client), "bridged", f"to server {qualified(server)} by {ctx.by()}", where
        )
