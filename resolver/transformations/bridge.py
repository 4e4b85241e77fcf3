"""``connect bridge A.T1 -> B.T2`` (topics) or ``connect bridge N.c -> M.s`` (a service):
an endpoint connection between two containers."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

from spl.diagnostics import location_of
from spl.dsl.rm_names import same_container_bridge
from spl.resolver.context import ResolutionContext, qualified
from spl.resolver.transformations.connect import here, server_decision, topic_named, type_mismatch
from spl.resolver.transformations.kind import (
    Decision,
    DecisionKey,
    Predictions,
    Questions,
    TransformationKind,
)


class ConnectBridge(TransformationKind):
    metaclass = "ConnectBridge"

    def apply(self, t: Any, ctx: ResolutionContext) -> None:
        where = location_of(t)
        if t.sourceTopic is not None:
            source = topic_named(ctx, t.sourceTopic, None, where)
            target = topic_named(ctx, t.targetTopic, None, where)
            if source is None or target is None or type_mismatch(ctx, source, target, where):
                return
            ctx.wiring.topic_bridge(source, target)
            for topic in (source, target):
                ctx.keep(topic, f"bridged by {ctx.by()}", where)
            ctx.trace.record(
                qualified(source), "bridged", f"to {qualified(target)} by {ctx.by()}", where
            )
            return
        client = ctx.copy_of(t.client)
        server = ctx.copy_of(t.server)
        if here(client) is here(server):
            ctx.sink.error(where, same_container_bridge(client, server, here(client)))
            return
        ctx.keep(client.eContainer(), f"its client {client.name} is bridged by {ctx.by()}", where)
        ctx.keep(server.eContainer(), f"its server {server.name} is bridged by {ctx.by()}", where)
        if ctx.decide("server", client, qualified(server), where):
            ctx.wiring.service_bridge(client, server)
            ctx.trace.record(
                qualified(client), "bridged", f"to server {qualified(server)} by {ctx.by()}", where
            )

    def touched(self, t: Any) -> Iterator[Any]:
        if t.client is not None:  # a topic bridge keeps its topics, not nodes
            yield t.client.eContainer()
            yield t.server.eContainer()

    def decisions(self, t: Any, element: Any, names: Any) -> Iterator[tuple[DecisionKey, Decision]]:
        return server_decision(t, element) if t.client is not None else iter(())

    def predict(self, t: Any, element: Any, effects: Predictions) -> None:
        if t.client is not None:
            effects.server(t.client, element, t.server, location_of(t))

    def questions(self, t: Any, ask: Callable[[], Questions]) -> Iterator[str | None]:
        if t.sourceTopic is not None:
            for end in (t.sourceTopic, t.targetTopic):
                yield ask().topic_lookup(None, end)
        else:
            yield ask().together(t.client, t.server)
