"""One kind of resolution statement (a ``.rm`` transformation), and all spl knows of it.

A kind is one class (one module of this package each): how it acts on the product being
derived (:meth:`TransformationKind.apply`, with the words its trace entries say), which
template elements an active statement keeps (:meth:`~TransformationKind.touched`) and
gives its feature's sharing mode (:meth:`~TransformationKind.shares`), what it decides
(:meth:`~TransformationKind.decisions`: two statements deciding one thing differently
conflict, SPL012), what it does to each node for the fleet analysis
(:meth:`~TransformationKind.predict`), and in which products it may fail
(:meth:`~TransformationKind.questions`, SPL016). The engine, the product-line checks
and the fleet analysis ask the kind of a statement
(:func:`spl.resolver.resolution.transformations.kind_of`) and never compare kind names; a
new kind is a new module and a line in the registry (docs/architecture.md).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Generic, NamedTuple, Protocol, TypeVar

from spl.core.diagnostics import Location

if TYPE_CHECKING:
    from spl.dsl.rm.names import Names
    from spl.metamodels import fm_types, rm_types, tsm_types
    from spl.resolver.resolution.context import ResolutionContext
    from spl.resolver.resolution.effects import EffectValue

# the rm.ecore class of the statements of one kind
Statement = TypeVar("Statement", bound="rm_types.Transformation")

DecisionKey = tuple[str, int]  # (what is decided, id of the template element decided on)


@dataclass(frozen=True)
class Decision:
    """What one transformation (or a feature's sharing mode) decides about one thing."""

    kind: str  # the engine's wording: implementation, value, period, migration target, ...
    subject: str  # the thing decided, as messages name it
    value: str
    element: rm_types.ResolutionElement  # the resolution element deciding
    location: Location | None
    # a topic decision: (container name, topic name); the container is None when it is
    # only known in a product (an unqualified name, a node some migration may move)
    topic: tuple[str | None, str] | None = None

    def differs(self, other: Decision) -> bool:
        """Whether the two decide differently in every product where both are taken."""
        if self.topic is None or other.topic is None:
            return self.value != other.value
        (container, name), (other_container, other_name) = self.topic, other.topic
        if name != other_name:
            return True
        return None not in (container, other_container) and container != other_container


class Binding(NamedTuple):
    """An interface a statement binds to a topic (by name; in ``container``, or where the
    node is when the statement runs if None) or to a server."""

    interface: tsm_types.Interface
    topic: str | None = None
    container: tsm_types.Container | None = None
    server: tsm_types.ServiceServer | None = None


class Predictions(Protocol):
    """The fleet analysis' table of what elements do to nodes
    (src/spl/resolver/resolution/effects.py)."""

    def effect(
        self,
        node: tsm_types.Node,
        aspect: str,
        element: rm_types.ResolutionElement,
        value: EffectValue,
        where: Location | None,
    ) -> None: ...

    def server(
        self,
        client: tsm_types.ServiceClient,
        element: rm_types.ResolutionElement,
        server: tsm_types.ServiceServer,
        where: Location | None,
    ) -> None: ...

    def topic_value(self, connect: rm_types.ConnectToTopic | rm_types.ConnectToNewTopic) -> str: ...


class Questions(Protocol):
    """SAT questions about one statement: each answers with the message of a product in
    which the statement fails, or None (src/spl/resolver/line_checks/lookups.py)."""

    def topic_lookup(
        self, node: tsm_types.Node | None, reference: rm_types.TopicReference
    ) -> str | None: ...

    def apart(
        self, client: tsm_types.ServiceClient, server: tsm_types.ServiceServer
    ) -> str | None: ...

    def together(
        self, client: tsm_types.ServiceClient, server: tsm_types.ServiceServer
    ) -> str | None: ...

    def onto_a_name(self, node: tsm_types.Node, target: tsm_types.Container) -> str | None: ...


class TransformationKind(Generic[Statement]):
    """The behaviour of one ``.rm`` metaclass (``Statement``, its class in rm.ecore);
    subclasses override what applies to them."""

    metaclass: ClassVar[str]  # the rm.ecore class of the statements of this kind

    def apply(self, t: Statement, ctx: ResolutionContext) -> None:
        """Act on the product as the statements before it left it (docs/semantics.md)."""
        raise NotImplementedError

    def touched(self, t: Statement) -> Iterator[tsm_types.Node | tsm_types.Store]:
        """The template nodes and stores an active statement keeps in the product."""
        return iter(())

    def rebinds(self, t: Statement) -> Iterator[Binding]:
        """The template interfaces whose topic or server an active statement changes, and
        to what: in products activating it their template flows may not hold, and new
        ones may (the dataflow line check, docs/semantics.md F8). A migration rebinds
        none: the endpoint rewiring keeps the template's flows (docs/resolution.md)."""
        return iter(())

    def routes(self, t: Statement) -> Iterator[tuple[rm_types.TopicReference, ...]]:
        """The (source, target) topics an active statement bridges: data on the source
        reaches the target's subscribers too (the dataflow line check)."""
        return iter(())

    def shares(self, t: Statement) -> Iterator[tsm_types.Node]:
        """The template nodes the statement's feature gives its sharing mode to (besides
        the element's required ones)."""
        return iter(())

    def decisions(
        self, t: Statement, element: rm_types.ResolutionElement, names: Names
    ) -> Iterator[tuple[DecisionKey, Decision]]:
        """What the statement decides when its element is active, keyed like the engine's
        registry of decisions (``ResolutionContext.decide``)."""
        return iter(())

    def predict(
        self, t: Statement, element: rm_types.ResolutionElement, effects: Predictions
    ) -> None:
        """Record in the fleet analysis' table what the statement does to nodes."""

    def questions(self, t: Statement, ask: Callable[[], Questions]) -> Iterator[str | None]:
        """For each way the statement can fail in some product, the witness message (a
        new question object per question: each asks the solver once)."""
        return iter(())

    def move(self, t: Statement) -> tuple[tsm_types.Node, tsm_types.Container] | None:
        """(node, target container) of a migration."""
        return None

    def attribute(self, t: Statement) -> fm_types.Attribute | None:
        """The feature attribute whose value the statement uses, if any."""
        return None

    def created_topic(self, t: Statement) -> tsm_types.Topic | None:
        """The topic a ``new topic`` statement declares."""
        return None
