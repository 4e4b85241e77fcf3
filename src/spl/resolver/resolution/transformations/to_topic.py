"""``connect NODE.i to topic [C.]T``: an interface bound to an existing topic."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

from spl.core.diagnostics import location_of
from spl.resolver.resolution.context import ResolutionContext
from spl.resolver.resolution.transformations.connect import (
    connect_interface,
    node_of,
    predict_topic,
    topic_decision,
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


class ConnectToTopic(TransformationKind["rm_types.ConnectToTopic"]):
    metaclass = "ConnectToTopic"

    def apply(self, t: rm_types.ConnectToTopic, ctx: ResolutionContext) -> None:
        where = location_of(t)
        interface = ctx.copy_of(t.interface)
        topic = topic_named(ctx, t.topic, node_of(interface), where)
        if topic is None or type_mismatch(ctx, interface, topic, where):
            return
        connect_interface(interface, topic, ctx, where)

    def rebinds(self, t: rm_types.ConnectToTopic) -> Iterator[Binding]:
        yield Binding(t.interface, t.topic.name, t.topic.container)

    def touched(self, t: rm_types.ConnectToTopic) -> Iterator[tsm_types.Node | tsm_types.Store]:
        yield node_of(t.interface)

    def decisions(
        self, t: rm_types.ConnectToTopic, element: rm_types.ResolutionElement, names: Names
    ) -> Iterator[tuple[DecisionKey, Decision]]:
        return topic_decision(t, element, names)

    def predict(
        self, t: rm_types.ConnectToTopic, element: rm_types.ResolutionElement, effects: Predictions
    ) -> None:
        predict_topic(t, element, effects)

    def questions(
        self, t: rm_types.ConnectToTopic, ask: Callable[[], Questions]
    ) -> Iterator[str | None]:
        yield ask().topic_lookup(node_of(t.interface), t.topic)
