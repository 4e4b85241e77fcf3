"""``connect NODE.i to topic [C.]T``: an interface bound to an existing topic."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

from spl.diagnostics import location_of
from spl.resolver.context import ResolutionContext
from spl.resolver.transformations.connect import (
    connect_interface,
    predict_topic,
    topic_decision,
    topic_named,
    type_mismatch,
)
from spl.resolver.transformations.kind import (
    Decision,
    DecisionKey,
    Predictions,
    Questions,
    TransformationKind,
)


class ConnectToTopic(TransformationKind):
    metaclass = "ConnectToTopic"

    def apply(self, t: Any, ctx: ResolutionContext) -> None:
        where = location_of(t)
        interface = ctx.copy_of(t.interface)
        topic = topic_named(ctx, t.topic, interface.eContainer(), where)
        if topic is None or type_mismatch(ctx, interface, topic, where):
            return
        connect_interface(interface, topic, ctx, where)

    def touched(self, t: Any) -> Iterator[Any]:
        yield t.interface.eContainer()

    def decisions(self, t: Any, element: Any, names: Any) -> Iterator[tuple[DecisionKey, Decision]]:
        return topic_decision(t, element, names)

    def predict(self, t: Any, element: Any, effects: Predictions) -> None:
        predict_topic(t, element, effects)

    def questions(self, t: Any, ask: Callable[[], Questions]) -> Iterator[str | None]:
        yield ask().topic_lookup(t.interface.eContainer(), t.topic)
