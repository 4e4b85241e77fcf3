"""State shared by the transformations of one resolution (docs/resolution.md, steps 2-4).

Transformations are plain functions ``apply(transformation, context)``; the context
gives them the copy of the template they act on, the kept-set bookkeeping, the
conflict registry (two active elements may not decide one thing differently) and
the trace.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, TypeVar, cast

from spl.core.diagnostics import DiagnosticSink, Location, location_of
from spl.metamodels import tsm
from spl.resolver.architecture.endpoints import EndpointWiring
from spl.resolver.architecture.product import NodeMigration
from spl.resolver.resolution.trace import Trace

if TYPE_CHECKING:
    from spl.metamodels import rm_types, tsm_types
    from spl.metamodels.model_types import EObject
    from spl.resolver.architecture.product import AttributeValue

Element = TypeVar("Element", bound="EObject")


def qualified(element: tsm_types.NamedElement) -> str:
    """The name the trace uses: nodes and containers by name (the .rm names them so),
    topics as ``Container.Topic``, interfaces as ``Node.interface``."""
    owner = element.eContainer()
    if owner is None or isinstance(element, tsm().Node):
        return element.name
    if isinstance(owner, tsm().Endpoint):
        return f"{owner.eContainer().name}.endpoint.{element.name}"
    if owner.eContainer() is None:
        return element.name
    return f"{qualified(cast('tsm_types.NamedElement', owner))}.{element.name}"


def subject_name(subject: tsm_types.NamedElement | tsm_types.Refinement) -> str:
    """What a decision is about, as messages and the trace name it: a refinement has no
    name of its own, so it is its store's and output's (``PositionStore.PositionInDEG``)."""
    if isinstance(subject, tsm().Refinement):
        return f"{qualified(subject.eContainer())}.{subject.output.name}"
    return qualified(cast("tsm_types.NamedElement", subject))


def describe(element: rm_types.ResolutionElement) -> str:
    """How a resolution element is named in messages: ``when Stereo selected (f:12:1)``."""
    state = "selected" if element.activeIfSelected else "not selected"
    return f"'when {element.feature.name} {state}' ({location_of(element)})"


@dataclass(frozen=True)
class Cause:
    """Why an interface left the container of its template flows, in words naming the
    resolution element and feature, and where the statement is."""

    text: str  # "MapOptimizer is migrated to Robot by 'when AdditionalPC selected' (...)"
    location: Location | None


@dataclass
class Decision:
    value: str
    element: rm_types.ResolutionElement | None  # the resolution element that decided
    where: Location | None


@dataclass
class ResolutionContext:
    system: tsm_types.System  # the copy of the template being transformed
    copies: dict[int, EObject]  # id(template element) -> its copy (an identity map)
    trace: Trace
    sink: DiagnosticSink
    attributes: dict[str, AttributeValue]  # "Feature.attr" -> value in this product
    kept: set[int] = field(default_factory=set)
    migrations: list[NodeMigration] = field(default_factory=list)
    decisions: dict[tuple[str, int], Decision] = field(default_factory=dict)
    created_topics: set[int] = field(default_factory=set)  # ids of topics `new topic` made
    # id of a migrated node or of an interface connected to another container's topic ->
    # why: the endpoint rewiring names it in every decision it takes for them
    displaced: dict[int, Cause] = field(default_factory=dict)
    # the template's nodes the copy left out (nothing can keep them, pruning.py), by the
    # id of the container of the copy holding theirs: a migration still finds their names
    left_out: dict[int, list[tsm_types.Node]] = field(default_factory=dict)
    # the active resolution element whose transformations run
    element: rm_types.ResolutionElement | None = None
    # id(container) -> its topics by name
    _topics: dict[int, dict[str, tsm_types.Topic]] = field(default_factory=dict)

    @cached_property
    def wiring(self) -> EndpointWiring:
        return EndpointWiring(self.system)

    def copy_of(self, template_element: Element) -> Element:
        return cast("Element", self.copies[id(template_element)])

    def keep(
        self, element: tsm_types.NamedElement, why: str, location: Location | None = None
    ) -> None:
        if id(element) not in self.kept:
            self.kept.add(id(element))
            self.trace.record(qualified(element), "kept", why, location)

    def by(self) -> str:
        return describe(cast("rm_types.ResolutionElement", self.element))  # set while they run

    def decide(
        self,
        kind: str,
        subject: tsm_types.NamedElement | tsm_types.Refinement,
        value: str,
        where: Location | None,
    ) -> bool:
        """Record a decision of the running element; a different earlier one is a conflict."""
        key = (kind, id(subject))
        earlier = self.decisions.get(key)
        if earlier is None:
            self.decisions[key] = Decision(value, self.element, where)
            return True
        if earlier.value != value:
            self.sink.error(
                where,
                f"conflict: {self.by()} gives {kind} {value} to {subject_name(subject)}, but "
                f"{describe(cast('rm_types.ResolutionElement', earlier.element))} gives "
                f"{earlier.value} (at {earlier.where})",
                code="SPL020",
            )
        return False

    def topic_named(self, container: tsm_types.Container, name: str) -> tsm_types.Topic | None:
        """Topic ``name`` of ``container`` as the product stands now: the template's copy or
        one an earlier `new topic` created (docs/semantics.md), else None."""
        return self._topic_index(container).get(name)

    def _topic_index(self, container: tsm_types.Container) -> dict[str, tsm_types.Topic]:
        index = self._topics.get(id(container))
        if index is None:
            index = self._topics[id(container)] = {t.name: t for t in container.topics}
        return index

    def is_created(self, topic: tsm_types.Topic) -> bool:
        return id(topic) in self.created_topics

    def create_topic(
        self, container: tsm_types.Container, declaration: tsm_types.Topic
    ) -> tsm_types.Topic:
        """The topic a `new topic` statement declares, created in ``container``."""
        name, kind, ros_name = declaration.name, declaration.type, declaration.rosName
        topic = tsm().Topic(name=name, type=kind, rosName=ros_name)
        topic.srcFile = declaration.srcFile
        topic.srcLine, topic.srcCol = declaration.srcLine, declaration.srcCol
        self._topic_index(container)[topic.name] = topic
        container.topics.append(topic)
        self.created_topics.add(id(topic))
        self.trace.record(
            qualified(topic),
            "created",
            f"new topic created by {self.by()}",
            location_of(declaration),
        )
        return topic
