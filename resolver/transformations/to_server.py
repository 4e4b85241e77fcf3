"""``connect NODE.c to server NODE.s``: a client bound to a server of its container."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

from spl.diagnostics import location_of
from spl.dsl.rm_names import not_served_here
from spl.resolver.context import ResolutionContext, qualified
from spl.resolver.transformations.connect import here, server_decision
from spl.resolver.transformations.kind import (
    Decision,
    DecisionKey,
    Predictions,
    Questions,
    TransformationKind,
)


class ConnectService(TransformationKind):
    metaclass = "ConnectService"

    def apply(self, t: Any, ctx: ResolutionContext) -> None:
        client = ctx.copy_of(t.client)
        server = ctx.copy_of(t.server)
        where = location_of(t)
        if here(client) is not here(server):
            message = not_served_here(t.client, t.server, [here(server)], [here(client)])
            ctx.sink.error(where, f"{message} (containers at this point)")
            return
        ctx.keep(client.eContainer(), f"its client {client.name} is connected by {ctx.by()}", where)
        ctx.keep(server.eContainer(), f"its server {server.name} is connected by {ctx.by()}", where)
        if ctx.decide("server", client, qualified(server), where):
            client.server = server
            reason = f"to server {qualified(server)} by {ctx.by()}"
            ctx.trace.record(qualified(client), "connected", reason, where)

    def touched(self, t: Any) -> Iterator[Any]:
        yield t.client.eContainer()
        yield t.server.eContainer()

    def decisions(self, t: Any, element: Any, names: Any) -> Iterator[tuple[DecisionKey, Decision]]:
        return server_decision(t, element)

    def predict(self, t: Any, element: Any, effects: Predictions) -> None:
        effects.server(t.client, element, t.server, location_of(t))

    def questions(self, t: Any, ask: Callable[[], Questions]) -> Iterator[str | None]:
        yield ask().apart(t.client, t.server)
