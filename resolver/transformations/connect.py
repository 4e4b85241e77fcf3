"""Connection transformations: the four kinds of seeds/003.

Interface to an existing topic, interface to a new topic, service client to server,
and a bridge between containers. Names were resolved against the template by the
.rm builder; here they are mapped onto the product's copy.
"""

from __future__ import annotations

from typing import Any

from spl.diagnostics import location_of
from spl.resolver.context import ResolutionContext, qualified


def _node_container(ctx: ResolutionContext, template_interface: Any) -> Any:
    """The container the node of a template interface has in the template."""
    return ctx.copy_of(template_interface.eContainer().eContainer())


def _connect_interface(transformation: Any, ctx: ResolutionContext) -> None:
    interface = ctx.copy_of(transformation.interface)
    topic = ctx.topic_for(_node_container(ctx, transformation.interface), transformation.topic)
    where = location_of(transformation)
    node = interface.eContainer()
    ctx.keep(node, f"its interface {interface.name} is connected by {ctx.by()}", where)
    ctx.keep(topic, f"{interface.name} of {node.name} is connected to it by {ctx.by()}", where)
    if ctx.decide("topic", interface, qualified(topic), where):
        interface.topic = topic
        ctx.trace.record(
            qualified(interface), "connected", f"to topic {qualified(topic)} by {ctx.by()}", where
        )


def to_topic(transformation: Any, ctx: ResolutionContext) -> None:
    _connect_interface(transformation, ctx)


def to_new_topic(transformation: Any, ctx: ResolutionContext) -> None:
    _connect_interface(transformation, ctx)


def to_server(transformation: Any, ctx: ResolutionContext) -> None:
    client = ctx.copy_of(transformation.client)
    server = ctx.copy_of(transformation.server)
    where = location_of(transformation)
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
        source = ctx.copy_of(transformation.sourceTopic)
        target = ctx.copy_of(transformation.targetTopic)
        ctx.wiring.topic_bridge(source, target)
        for topic in (source, target):
            ctx.keep(topic, f"bridged by {ctx.by()}", where)
        ctx.trace.record(
            qualified(source), "bridged", f"to {qualified(target)} by {ctx.by()}", where
        )
        return
    client = ctx.copy_of(transformation.client)
    server = ctx.copy_of(transformation.server)
    ctx.keep(client.eContainer(), f"its client {client.name} is bridged by {ctx.by()}", where)
    ctx.keep(server.eContainer(), f"its server {server.name} is bridged by {ctx.by()}", where)
    if ctx.decide("server", client, qualified(server), where):
        ctx.wiring.service_bridge(client, server)
        ctx.trace.record(
            qualified(client), "bridged", f"to server {qualified(server)} by {ctx.by()}", where
        )
