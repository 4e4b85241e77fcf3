"""``connect bridge A.T1 -> B.T2`` (topics) or ``connect bridge N.c -> M.s`` (a service):
an endpoint connection between two containers."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import location_of
from spl.dsl.rm.messages import same_container_bridge
from spl.resolver.resolution.context import ResolutionContext, qualified
from spl.resolver.resolution.transformations.connect import (
    here,
    node_of,
    server_decision,
    topic_named,
    type_mismatch,
)
from spl.resolver.resolution.transformations.kind import (
    Binding,
    Decision,
    DecisionKey,
    Predictions,
    Questions,
    TransformationKind,
)

if TYPE_CHECKING:
    from spl.dsl.rm.names import Names
    from spl.metamodels import rm_types, tsm_types


class ConnectBridge(TransformationKind["rm_types.ConnectBridge"]):
    metaclass = "ConnectBridge"

    def apply(self, t: rm_types.ConnectBridge, ctx: ResolutionContext) -> None:
        where = location_of(t)
        if t.sourceTopic is not None:
            source_end, target_end = _topics(t)
            source = topic_named(ctx, source_end, None, where)
            target = topic_named(ctx, target_end, None, where)
            if source is None or target is None or type_mismatch(ctx, source, target, where):
                return
            ctx.wiring.topic_bridge(source, target)
            for topic in (source, target):
                ctx.keep(topic, f"bridged by {ctx.by()}", where)
            ctx.trace.record(
                qualified(source), "bridged", f"to {qualified(target)} by {ctx.by()}", where
            )
            return
        template_client, template_server = _service(t)
        client, server = ctx.copy_of(template_client), ctx.copy_of(template_server)
        if here(client) is here(server):
            ctx.sink.error(where, same_container_bridge(client, server, here(client)))
            return
        ctx.keep(node_of(client), f"its client {client.name} is bridged by {ctx.by()}", where)
        ctx.keep(node_of(server), f"its server {server.name} is bridged by {ctx.by()}", where)
        if ctx.decide("server", client, qualified(server), where):
            ctx.wiring.service_bridge(client, server)
            ctx.trace.record(
                qualified(client), "bridged", f"to server {qualified(server)} by {ctx.by()}", where
            )

    def rebinds(self, t: rm_types.ConnectBridge) -> Iterator[Binding]:
        if t.client is not None:  # a topic bridge adds routes and rebinds nothing
            client, server = _service(t)
            yield Binding(client, server=server)

    def routes(self, t: rm_types.ConnectBridge) -> Iterator[tuple[rm_types.TopicReference, ...]]:
        if t.sourceTopic is not None:
            yield _topics(t)

    def touched(self, t: rm_types.ConnectBridge) -> Iterator[tsm_types.Node | tsm_types.Store]:
        if t.client is not None:  # a topic bridge keeps its topics, not nodes
            client, server = _service(t)
            yield node_of(client)
            yield node_of(server)

    def decisions(
        self, t: rm_types.ConnectBridge, element: rm_types.ResolutionElement, names: Names
    ) -> Iterator[tuple[DecisionKey, Decision]]:
        return server_decision(t, element) if t.client is not None else iter(())

    def predict(
        self, t: rm_types.ConnectBridge, element: rm_types.ResolutionElement, effects: Predictions
    ) -> None:
        if t.client is not None:
            client, server = _service(t)
            effects.server(client, element, server, location_of(t))

    def questions(
        self, t: rm_types.ConnectBridge, ask: Callable[[], Questions]
    ) -> Iterator[str | None]:
        if t.sourceTopic is not None:
            for end in _topics(t):
                yield ask().topic_lookup(None, end)
        else:
            yield ask().together(*_service(t))


def _topics(t: rm_types.ConnectBridge) -> tuple[rm_types.TopicReference, rm_types.TopicReference]:
    """The two ends of a topic bridge (the .rm sets both, or neither)."""
    return cast(
        "tuple[rm_types.TopicReference, rm_types.TopicReference]", (t.sourceTopic, t.targetTopic)
    )


def _service(t: rm_types.ConnectBridge) -> tuple[tsm_types.ServiceClient, tsm_types.ServiceServer]:
    """The client and server of a service bridge (the .rm sets both, or neither)."""
    return cast("tuple[tsm_types.ServiceClient, tsm_types.ServiceServer]", (t.client, t.server))
