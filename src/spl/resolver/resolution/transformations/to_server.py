"""``connect NODE.c to server NODE.s``: a client bound to a server of its container."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import location_of
from spl.dsl.rm.messages import not_served_here
from spl.resolver.resolution.context import ResolutionContext, qualified
from spl.resolver.resolution.transformations.connect import here, node_of, server_decision
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


def _pair(t: rm_types.ConnectService) -> tuple[tsm_types.ServiceClient, tsm_types.ServiceServer]:
    """The client and server a statement binds: a service's, or an action's, which binds
    the same way (the .rm builder checked that the kinds agree, docs/rm.md)."""
    return cast("tsm_types.ServiceClient", t.client), cast("tsm_types.ServiceServer", t.server)


class ConnectService(TransformationKind["rm_types.ConnectService"]):
    metaclass = "ConnectService"

    def apply(self, t: rm_types.ConnectService, ctx: ResolutionContext) -> None:
        ends = _pair(t)
        client, server = ctx.copy_of(ends[0]), ctx.copy_of(ends[1])
        where = location_of(t)
        if here(client) is not here(server):
            message = not_served_here(*_pair(t), [here(server)], [here(client)])
            ctx.sink.error(where, f"{message} (containers at this point)")
            return
        ctx.keep(node_of(client), f"its client {client.name} is connected by {ctx.by()}", where)
        ctx.keep(node_of(server), f"its server {server.name} is connected by {ctx.by()}", where)
        if ctx.decide("server", client, qualified(server), where):
            client.server = server
            reason = f"to server {qualified(server)} by {ctx.by()}"
            ctx.trace.record(qualified(client), "connected", reason, where)

    def rebinds(self, t: rm_types.ConnectService) -> Iterator[Binding]:
        client, server = _pair(t)
        yield Binding(client, server=server)

    def touched(self, t: rm_types.ConnectService) -> Iterator[tsm_types.Node | tsm_types.Store]:
        yield node_of(t.client)
        yield node_of(t.server)

    def decisions(
        self, t: rm_types.ConnectService, element: rm_types.ResolutionElement, names: Names
    ) -> Iterator[tuple[DecisionKey, Decision]]:
        return server_decision(t, element)

    def predict(
        self, t: rm_types.ConnectService, element: rm_types.ResolutionElement, effects: Predictions
    ) -> None:
        client, server = _pair(t)
        effects.server(client, element, server, location_of(t))

    def questions(
        self, t: rm_types.ConnectService, ask: Callable[[], Questions]
    ) -> Iterator[str | None]:
        yield ask().apart(*_pair(t))
