"""State shared by the transformations of one resolution (SPEC 5.1 steps 3-6).

Transformations are plain functions ``apply(transformation, context)``; the context
gives them the copy of the template they act on, the kept-set bookkeeping, the
conflict registry (two active elements may not decide one thing differently) and
the trace.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

from spl.diagnostics import DiagnosticSink, Location, location_of
from spl.metamodels import tsm
from spl.resolver.endpoints import EndpointWiring
from spl.resolver.product import NodeMigration
from spl.resolver.trace import Trace


def qualified(element: Any) -> str:
    """The name the trace uses: nodes and containers by name (the .rm names them so),
    topics as ``Container.Topic``, interfaces as ``Node.interface``."""
    owner = element.eContainer()
    if owner is None or isinstance(element, tsm().Node):
        return element.name
    if isinstance(owner, tsm().Endpoint):
        return f"{owner.eContainer().name}.endpoint.{element.name}"
    return f"{qualified(owner)}.{element.name}" if owner.eContainer() is not None else element.name


def describe(element: Any) -> str:
    """How a resolution element is named in messages: ``when Stereo selected (f:12:1)``."""
    state = "selected" if element.activeIfSelected else "not selected"
    return f"'when {element.feature.name} {state}' ({location_of(element)})"


@dataclass
class Decision:
    value: Any
    element: Any  # the resolution element that decided
    where: Location | None


@dataclass
class ResolutionContext:
    system: Any  # the copy of the template being transformed
    copies: dict[int, Any]  # id(template element) -> its copy
    trace: Trace
    sink: DiagnosticSink
    attributes: dict[str, Any]  # "Feature.attr" -> value in this product
    kept: set[int] = field(default_factory=set)
    migrations: list[NodeMigration] = field(default_factory=list)
    decisions: dict[tuple[str, int], Decision] = field(default_factory=dict)
    created_topics: dict[tuple[str, str], Any] = field(default_factory=dict)
    element: Any = None  # the active resolution element whose transformations run

    @cached_property
    def wiring(self) -> EndpointWiring:
        return EndpointWiring(self.system)

    def copy_of(self, template_element: Any) -> Any:
        return self.copies[id(template_element)]

    def keep(self, element: Any, why: str, location: Location | None = None) -> None:
        if id(element) not in self.kept:
            self.kept.add(id(element))
            self.trace.record(qualified(element), "kept", why, location)

    def by(self) -> str:
        return describe(self.element)

    def decide(self, kind: str, subject: Any, value: Any, where: Location | None) -> bool:
        """Record a decision of the running element; a different earlier one is a conflict."""
        key = (kind, id(subject))
        earlier = self.decisions.get(key)
        if earlier is None:
            self.decisions[key] = Decision(value, self.element, where)
            return True
        if earlier.value != value:
            self.sink.error(
                where,
                f"conflict: {self.by()} gives {kind} {value} to {qualified(subject)}, but "
                f"{describe(earlier.element)} gives {earlier.value} (at {earlier.where})",
                code="SPL020",
            )
        return False

    def topic_for(self, container: Any, template_topic: Any) -> Any:
        """The product's copy of a template topic, or the topic a `new topic` created."""
        copy = self.copies.get(id(template_topic))
        if copy is not None:
            return copy
        key = (container.name, template_topic.name)
        topic = self.created_topics.get(key)
        if topic is None:
            T = tsm()
            topic = T.Topic(
                name=template_topic.name, type=template_topic.type, rosName=template_topic.rosName
            )
            topic.srcFile = template_topic.srcFile
            topic.srcLine, topic.srcCol = template_topic.srcLine, template_topic.srcCol
            container.topics.append(topic)
            self.created_topics[key] = topic
            self.trace.record(
                qualified(topic),
                "created",
                f"new topic created by {self.by()}",
                location_of(template_topic),
            )
        return topic
