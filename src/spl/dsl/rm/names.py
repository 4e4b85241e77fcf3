"""What the names of a resolution model mean (docs/semantics.md), decided in one place.

The .rm builder (:mod:`spl.dsl.rm.language`) reads every reference through :class:`Names`, and
the product-line checks walk the parsed model with the same class, so a name means one
thing everywhere.

Statements run in file order, each seeing the model the statements before it left
(docs/resolution.md, step 3). Before a product is chosen it is not known which elements are
active, so :class:`Names` follows the model as far as it is known statically: the
containers a node can be in at a statement (the one declaring it in the .tsm, or one an
earlier migration may have moved it to) and the topics that can exist there (the
.tsm's, and those an earlier ``new topic`` may have created). A statement is refused at
parse time when it fails wherever its node can be; the Resolution Engine checks it
again against the product it derives (:mod:`spl.resolver.resolution.transformations`).
"""

from __future__ import annotations

from collections import defaultdict
from typing import TYPE_CHECKING, Literal, NamedTuple, TypeVar, cast, overload

from spl.dsl.rm.messages import candidates, missing_topic
from spl.metamodels import tsm

if TYPE_CHECKING:
    from spl.metamodels import rm_types, tsm_types
    from spl.metamodels.model_types import EObject

    Member = tsm_types.Node | tsm_types.Store  # what the .rm names by NAME or CONTAINER.NAME

Meaning = TypeVar("Meaning")

# the statements, as read, whose transformations change what the names of the
# statements after them mean (:meth:`Names.apply`): a migration, a topic created
CHANGING_STATEMENTS = frozenset(("MigrateStmt", "ConnectNewTopicStmt"))

BRIDGE_FORMS = (
    "a bridge is CONTAINER.TOPIC -> CONTAINER.TOPIC or "
    "[CONTAINER.]NODE.CLIENT -> [CONTAINER.]NODE.SERVER"
)


class NameProblem(Exception):
    """A reference that names nothing, or more than one thing; the message says which."""


class BridgeEnd(NamedTuple):
    """One end of ``connect bridge``: a topic of a container, or a service interface."""

    container: tsm_types.Container | None  # the topic's container; None for an interface
    # the .tsm topic or the `new topic` declaration; None for an interface
    topic: tsm_types.Topic | None
    interface: tsm_types.Interface | None  # None for a topic


class Placement(NamedTuple):
    """Where a node can be at one statement of a resolution model (docs/semantics.md C1)."""

    node: tsm_types.Node
    # the target of a migration earlier in the same element, or None
    certain: tsm_types.Container | None
    # (target, element) of migrations in earlier elements
    moves: tuple[tuple[tsm_types.Container, rm_types.ResolutionElement], ...]

    @property
    def places(self) -> list[tsm_types.Container]:
        """The containers the node can be in, the declaring one first.

        A migration earlier in the same element decides it (the element is active when
        the statement runs); migrations of earlier elements only may have happened."""
        if self.certain is not None:
            return [self.certain]
        found = [self.node.eContainer()]
        for target, _ in self.moves:
            if all(target is not c for c in found):
                found.append(target)
        return found


class Creation(NamedTuple):
    """A `new topic` statement that may create a topic: its element, and where its node
    could be (it creates the topic in the container the node is in)."""

    element: rm_types.ResolutionElement
    placement: Placement


class Names:
    """Resolves .rm references against a .tsm, following the model in file order."""

    def __init__(self, system: tsm_types.System) -> None:
        self.T = tsm()
        self.containers = {c.name: c for c in system.containers}
        self.declared: dict[str, list[Member]] = defaultdict(list)  # node and store names
        for container in system.containers:
            for member in [*container.nodes, *container.stores]:
                self.declared[member.name].append(member)
        self._topics = {(id(c), t.name): t for c in system.containers for t in c.topics}
        # first `new topic` declaration
        self._created: dict[tuple[int, str], tsm_types.Topic] = {}
        # the topics of each container by ROS name: the .tsm's, then those created
        self._ros_names: dict[tuple[int, str], list[tsm_types.Topic]] = defaultdict(list)
        for c in system.containers:
            for t in c.topics:
                self._ros_names[(id(c), t.rosName)].append(t)
        self._creators: dict[tuple[int, str], list[Creation]] = defaultdict(list)
        # the running resolution element
        self._element: rm_types.ResolutionElement | None = None
        # migrations of earlier elements, node id -> [(target, element)], and of earlier
        # statements of the running element, node id -> target
        self._may_move: dict[int, list[tuple[tsm_types.Container, rm_types.ResolutionElement]]] = (
            defaultdict(list)
        )
        self._moved: dict[int, tsm_types.Container] = {}

    # -- the model as statements leave it ------------------------------------------------
    def begin_element(self, element: rm_types.ResolutionElement | None = None) -> None:
        """The next resolution element starts: the migrations of the one before become
        possible (its feature may be off), no longer certain."""
        for node_id, target in self._moved.items():  # (moved by a running element)
            moved_by = cast("rm_types.ResolutionElement", self._element)
            self._may_move[node_id].append((target, moved_by))
        self._moved = {}
        self._element = element

    def taken(self, element: rm_types.ResolutionElement) -> rm_types.ResolutionElement:
        """``element``, built before from the same text in the same state (:mod:`.reuse`),
        taken over: what it changes for the statements after it, as its build did."""
        self.begin_element(element)
        for transformation in element.transformations:
            self.apply(transformation)
        return element

    def placement(self, node: tsm_types.Node) -> Placement:
        """Where ``node`` can be at the running statement."""
        return Placement(node, self._moved.get(id(node)), tuple(self._may_move.get(id(node), ())))

    def places(self, node: tsm_types.Node) -> list[tsm_types.Container]:
        return self.placement(node).places

    def apply(self, transformation: rm_types.Transformation) -> None:
        """What a statement of the running element changes for the statements after it."""
        kind = transformation.eClass.name
        if kind == "NodeMigration":
            migration = cast("rm_types.NodeMigration", transformation)
            self._moved[id(migration.node)] = migration.target
        elif kind == "ConnectToNewTopic":
            connect = cast("rm_types.ConnectToNewTopic", transformation)
            placement = self.placement(cast("tsm_types.Node", connect.interface.eContainer()))
            topic = connect.topic
            for container in placement.places:
                key = (id(container), topic.name)
                if key not in self._created:
                    self._created[key] = topic
                    self._ros_names[(id(container), topic.rosName)].append(topic)
                creator = cast("rm_types.ResolutionElement", self._element)  # the running one
                self._creators[key].append(Creation(creator, placement))

    def topic(self, container: tsm_types.Container, name: str) -> tsm_types.Topic | None:
        """Topic ``name`` of ``container`` (the .tsm's or an earlier `new topic`'s), or None."""
        key = (id(container), name)
        return self._topics.get(key) or self._created.get(key)

    def ros_name_taken(
        self, container: tsm_types.Container, topic: tsm_types.Topic
    ) -> tsm_types.Topic | None:
        """A topic of ``container`` (the .tsm's or an earlier `new topic`'s) under the ROS
        name of ``topic`` with another message type, or None."""
        others = self._ros_names.get((id(container), topic.rosName), ())
        return next((other for other in others if other.type != topic.type), None)

    def declared_topic(self, container: tsm_types.Container, name: str) -> bool:
        return (id(container), name) in self._topics

    def creations(self, container: tsm_types.Container, name: str) -> list[Creation]:
        """The `new topic` statements so far that may create ``name`` in ``container``."""
        return list(self._creators.get((id(container), name), ()))

    def is_created(self, topic: tsm_types.Topic) -> bool:
        return not isinstance(topic.eContainer(), self.T.Container)

    # -- references -----------------------------------------------------------------------
    def container(self, name: str) -> tsm_types.Container:
        found = self.containers.get(name)
        if found is None:
            raise NameProblem(f"unknown container {name}")
        return found

    @overload
    def element(self, ref: str) -> tsm_types.Node: ...

    @overload
    def element(self, ref: str, what: Literal["node"]) -> tsm_types.Node: ...

    @overload
    def element(self, ref: str, what: Literal["store"]) -> tsm_types.Store: ...

    @overload
    def element(self, ref: str, what: str) -> Member: ...

    def element(self, ref: str, what: str = "node") -> Member:
        """``NAME`` or ``CONTAINER.NAME``: a node, a store, or either ("node or store").

        The container is the one declaring the element in the .tsm; an unqualified name
        declared in more than one container is ambiguous."""
        parts = ref.split(".")
        if len(parts) > 2:
            raise NameProblem(f"{ref}: expected {what} NAME or CONTAINER.NAME")
        name = parts[-1]
        found = [m for m in self.declared.get(name, ()) if self._is(m, what)]
        if len(parts) == 2:
            container = self.container(parts[0])
            here = [m for m in found if m.eContainer() is container]
            if here:
                return here[0]
            if found:
                homes = " and ".join(m.eContainer().name for m in found)
                raise NameProblem(
                    f"no {what} {name} is declared in container {container.name} "
                    f"({name} is declared in {homes}; a node is qualified by the container "
                    "that declares it, wherever migrations move it)"
                )
            raise NameProblem(f"unknown {what} {ref}")
        if not found:
            raise NameProblem(f"unknown {what} {name}")
        if len(found) > 1:
            listed = candidates(
                [(f"{self._kind(m)} {m.eContainer().name}.{name}", m) for m in found]
            )
            raise NameProblem(f"{name} is ambiguous: {listed}; qualify it with its container")
        return found[0]

    def declared_node(self, container: tsm_types.Container, name: str) -> tsm_types.Node | None:
        """The node ``name`` the template declares in ``container`` (looked up, not
        searched: a line migrating many nodes of a large container asks often)."""
        for member in self.declared.get(name, ()):
            if isinstance(member, self.T.Node) and member.eContainer() is container:
                return member
        return None

    def _kind(self, member: Member) -> str:
        return "store" if isinstance(member, self.T.Store) else "node"

    def _is(self, member: Member, what: str) -> bool:
        if what == "node":
            return isinstance(member, self.T.Node)
        if what == "store":
            return isinstance(member, self.T.Store)
        return True

    def member(self, ref: str, attr: str, what: str) -> tsm_types.NamedElement:
        """``[CONTAINER.]NODE.NAME``: an interface or parameter of a node."""
        parts = ref.split(".")
        if not 2 <= len(parts) <= 3:
            raise NameProblem(f"{ref}: expected NODE.{what} or CONTAINER.NODE.{what}")
        node = self.element(".".join(parts[:-1]))
        members: list[tsm_types.NamedElement] = getattr(node, attr)
        found = next((x for x in members if x.name == parts[-1]), None)
        if found is None:
            raise NameProblem(f"node {node.name} has no {what} {parts[-1]}")
        return found

    def interface(self, ref: str) -> tsm_types.Interface:
        return cast("tsm_types.Interface", self.member(ref, "interfaces", "interface"))

    def topic_reference(
        self, ref: str, node: tsm_types.Node
    ) -> tuple[tsm_types.Container | None, list[tsm_types.Topic]]:
        """What ``to topic REF`` names for an interface of ``node``: the container written
        (None when unqualified) and the topics it can be at this statement, never empty.

        ``CONTAINER.TOPIC`` is that container's topic. ``TOPIC`` is looked up where the
        node is when the statement runs; statically, wherever it can be."""
        parts = ref.split(".")
        if len(parts) > 2:
            raise NameProblem(f"{ref}: expected TOPIC or CONTAINER.TOPIC")
        if len(parts) == 2:
            container = self.container(parts[0])
            topic = self.topic(container, parts[1])
            if topic is None:
                raise NameProblem(f"unknown topic {parts[1]} in container {container.name}")
            return container, [topic]
        places = self.places(node)
        found = [t for c in places if (t := self.topic(c, ref)) is not None]
        if not found:
            raise NameProblem(missing_topic(ref, node, places))
        return None, found

    def bridge_end(self, ref: str) -> BridgeEnd:
        """One end of ``connect bridge``. ``X.Y`` is topic Y of container X or interface Y
        of node X, decided by the model: when both exist the reference is ambiguous."""
        parts = ref.split(".")
        if len(parts) == 3:
            return BridgeEnd(None, None, self.interface(ref))
        if len(parts) != 2:
            raise NameProblem(BRIDGE_FORMS)
        readings: list[tuple[str, EObject, BridgeEnd]] = []
        problems: list[str] = []
        container = self.containers.get(parts[0])
        if container is not None:
            topic = self.topic(container, parts[1])
            if topic is not None:
                label = f"topic {parts[1]} of container {parts[0]}"
                readings.append((label, topic, BridgeEnd(container, topic, None)))
            else:
                problems.append(f"unknown topic {parts[1]} in container {parts[0]}")
        if parts[0] in self.declared:
            try:
                interface = self.interface(ref)
                label = f"interface {parts[1]} of node {parts[0]}"
                readings.append((label, interface, BridgeEnd(None, None, interface)))
            except NameProblem as problem:
                problems.append(str(problem))
        return _one_reading(ref, readings, problems, f"unknown container or node {parts[0]}")

    def parameter(self, ref: str) -> tuple[tsm_types.Parameter | None, tsm_types.Refinement | None]:
        """(parameter, refinement), one of them None: ``[CONTAINER.]NODE.PARAMETER`` or
        ``[CONTAINER.]STORE.REFINED_TYPE.period`` (a store's transformer period); when
        both readings exist the reference is ambiguous."""
        parts = ref.split(".")
        readings: list[
            tuple[str, EObject, tuple[tsm_types.Parameter | None, tsm_types.Refinement | None]]
        ] = []
        problems: list[str] = []
        named_store = len(parts) >= 3 and any(
            self._is(m, "store") for m in self.declared.get(parts[-3], ())
        )
        if len(parts) in (3, 4) and parts[-1] == "period" and named_store:
            try:
                store = self.element(".".join(parts[:-2]), "store")
                refinement = next(
                    (r for r in store.refinements if r.output.name == parts[-2]), None
                )
                if refinement is None:
                    raise NameProblem(f"store {store.name} has no refinement into {parts[-2]}")
                label = f"the period of store {store.name}'s refinement into {parts[-2]}"
                readings.append((label, refinement, (None, refinement)))
            except NameProblem as problem:
                problems.append(str(problem))
        if len(parts) in (2, 3):
            try:
                parameter = cast("tsm_types.Parameter", self.member(ref, "parameters", "parameter"))
                label = f"parameter {parameter.name} of node {parameter.eContainer().name}"
                readings.append((label, parameter, (parameter, None)))
            except NameProblem as problem:
                problems.append(str(problem))
        return _one_reading(ref, readings, problems, f"{ref}: expected NODE.PARAMETER")


def _one_reading(
    ref: str, readings: list[tuple[str, EObject, Meaning]], problems: list[str], unknown: str
) -> Meaning:
    """The meaning of a dotted name that has exactly one reading; two readings are an
    ambiguity naming both, none the first reading's problem (else ``unknown``)."""
    if len(readings) > 1:
        listed = candidates([(label, element) for label, element, _ in readings])
        raise NameProblem(f"{ref} is ambiguous: {listed}")
    if not readings:
        raise NameProblem(problems[0] if problems else unknown)
    return readings[0][2]
