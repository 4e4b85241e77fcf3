"""``connect NODE.i to new topic T : pkg/Type [name "/ros"]``: a topic created where the
node is at that statement, the interface bound to it."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from spl.core.diagnostics import location_of
from spl.dsl.rm.messages import new_topic_clash, same_topic
from spl.resolver.resolution.context import ResolutionContext
from spl.resolver.resolution.transformations.connect import (
    connect_interface,
    here,
    node_of,
    predict_topic,
    topic_decision,
)
from spl.resolver.resolution.transformations.kind import (
    Binding,
    Decision,
    DecisionKey,
    Predictions,
    TransformationKind,
)

if TYPE_CHECKING:
    from spl.dsl.rm.names import Names
    from spl.metamodels import rm_types, tsm_types


class ConnectToNewTopic(TransformationKind["rm_types.ConnectToNewTopic"]):
    metaclass = "ConnectToNewTopic"

    def apply(self, t: rm_types.ConnectToNewTopic, ctx: ResolutionContext) -> None:
        """Creates the topic where the interface's node is now; a topic of that name
        already there is only accepted when an earlier `new topic` made it alike."""
        where = location_of(t)
        interface = ctx.copy_of(t.interface)
        declaration = t.topic
        container = here(interface)
        topic = ctx.topic_named(container, declaration.name)
        if topic is None:
            topic = ctx.create_topic(container, declaration)
        elif not (ctx.is_created(topic) and same_topic(topic, declaration)):
            clash = new_topic_clash(declaration.name, container, topic, ctx.is_created(topic))
            ctx.sink.error(where, clash)
            return
        connect_interface(interface, topic, ctx, where)

    def rebinds(self, t: rm_types.ConnectToNewTopic) -> Iterator[Binding]:
        yield Binding(t.interface, t.topic.name)

    def touched(self, t: rm_types.ConnectToNewTopic) -> Iterator[tsm_types.Node | tsm_types.Store]:
        yield node_of(t.interface)

    def decisions(
        self, t: rm_types.ConnectToNewTopic, element: rm_types.ResolutionElement, names: Names
    ) -> Iterator[tuple[DecisionKey, Decision]]:
        return topic_decision(t, element, names)

    def predict(
        self,
        t: rm_types.ConnectToNewTopic,
        element: rm_types.ResolutionElement,
        effects: Predictions,
    ) -> None:
        predict_topic(t, element, effects)

    def created_topic(self, t: rm_types.ConnectToNewTopic) -> tsm_types.Topic | None:
        return t.topic
