"""SPL016: statements that resolve in some products of a line and fail in others.

A statement sees the product as the statements before it left it (docs/semantics.md
O1), so what it names can depend on which elements are active: a topic that exists
only where another element's migration moves the node, or only once another element's
`new topic` created it; a client and server that share a container only after some
migration. The .rm builder refuses a statement that fails in every case (C1); the ones
that fail in some products only are found here, each with a witness product, so
``spl check`` reports what ``spl validate --all`` would find product by product.

Each question is one SAT call: "a product activating the statement's element in which
the statement fails". Where a node is and whether a topic exists are written as
formulas over activation literals (``at`` and ``exists``). A topic that a `new topic`
may have created counts as existing whenever its creating element is active, so a
report is never made for a product in which the statement would succeed.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from functools import partial
from typing import Any, NamedTuple

from spl.diagnostics import Diagnostic, location_of
from spl.dsl.rm_names import Names, name_taken, not_served_here, same_container_bridge
from spl.resolver.activation import ActivationSolver
from spl.resolver.product_line import ProductLine

PRODUCT_DEPENDENT = "SPL016"


class Condition(NamedTuple):
    """A formula over activation literals: a disjunction ("any") or a conjunction ("all")."""

    kind: str
    literals: tuple[int, ...]

    def negated(self) -> Condition:
        return Condition("all" if self.kind == "any" else "any", tuple(-x for x in self.literals))

    @property
    def constant(self) -> bool | None:
        """True or False when the condition holds in every product or in none."""
        if self.literals:
            return None
        return self.kind == "all"

    def implied_by(self, variable: int) -> list[list[int]]:
        """Clauses for ``variable -> self``."""
        if self.kind == "any":
            return [[-variable, *self.literals]]
        return [[-variable, x] for x in self.literals]


ALWAYS = Condition("all", ())
NEVER = Condition("any", ())


class _Statement:
    """One statement's questions, asked with the model as the statements before it left it."""

    def __init__(self, solver: ActivationSolver, names: Names, element: Any) -> None:
        self.solver, self.names, self.element = solver, names, element
        self.clauses: list[list[int]] = []

    def at(self, node: Any, place: Any) -> Condition:
        """``node`` is in ``place`` when the statement runs."""
        if self.names.migrated_here(node):
            return ALWAYS if place is self.names.places(node)[0] else NEVER
        moves = self.names.migrations(node)
        if place is node.eContainer():
            return Condition("all", tuple(-self.solver.literal(e) for _, e in moves))
        return Condition("any", tuple(self.solver.literal(e) for t, e in moves if t is place))

    def exists(self, container: Any, name: str) -> Condition:
        """Topic ``name`` exists in ``container`` when the statement runs (or may)."""
        if self.names.declared_topic(container, name):
            return ALWAYS
        creators = self.names.creators(container, name)
        if any(e is self.element for e in creators):
            return ALWAYS
        return Condition("any", tuple(self.solver.literal(e) for e in creators))

    def one_of(self, conditions: list[Condition]) -> bool:
        """Require that one of ``conditions`` holds; False when none can."""
        options = []
        for condition in conditions:
            if condition.constant is True:
                return True
            if condition.constant is None:
                variable = self.solver.fresh()
                self.clauses += condition.implied_by(variable)
                options.append(variable)
        if options:
            self.clauses.append(options)
        return bool(options)

    def both(self, first: Condition, second: Condition) -> int | None:
        """A variable implying both conditions, or None when they never hold together."""
        if NEVER in (first, second):
            return None
        variable = self.solver.fresh()
        self.clauses += first.implied_by(variable) + second.implied_by(variable)
        return variable

    def witness(self) -> tuple[str, ...] | None:
        return self.solver.witness_where(self.element, self.clauses)


def product_dependent_statements(line: ProductLine, solver: ActivationSolver) -> list[Diagnostic]:
    """Statements that fail in some product activating their element (SPL016)."""
    names = Names(line.tsm)
    found = []
    for element in line.rm.elements:
        names.begin_element(element)
        for transformation in element.transformations:
            asked = partial(_Statement, solver, names, element)
            for problem in _failing(transformation, asked):
                found.append(
                    Diagnostic(location_of(transformation), problem, "error", PRODUCT_DEPENDENT)
                )
            names.apply(transformation)
    return found


def _failing(t: Any, statement: Callable[[], _Statement]) -> Iterator[str]:
    """The message for a product in which transformation ``t`` fails, one per question
    (a topic bridge asks about each of its two ends)."""
    kind = t.eClass.name
    if kind == "ConnectToTopic":
        found = [_topic_lookup(statement(), t.interface.eContainer(), t.topic)]
    elif kind == "ConnectBridge" and t.sourceTopic is not None:
        found = [_topic_lookup(statement(), None, end) for end in (t.sourceTopic, t.targetTopic)]
    elif kind == "ConnectService":
        found = [_apart(statement(), t.client, t.server)]
    elif kind == "ConnectBridge":
        found = [_together(statement(), t.client, t.server)]
    elif kind == "NodeMigration":
        found = [_onto_a_name(statement(), t.node, t.target)]
    else:
        found = []
    yield from (problem for problem in found if problem is not None)


def _topic_lookup(statement: _Statement, node: Any, reference: Any) -> str | None:
    """O1/T1/T2/T4: the topic named is missing where it is looked up."""
    places = [reference.container] if reference.container is not None else None
    for place in places or statement.names.places(node):
        missing = statement.exists(place, reference.name).negated()
        elsewhere = NEVER if places else statement.at(node, place).negated()
        if not statement.one_of([elsewhere, missing]):
            return None  # found there in every product
    witness = statement.witness()
    if witness is None:
        return None
    if places:
        problem = f"unknown topic {reference.name} in container {reference.container.name}"
    else:
        place = _place(statement, node, witness)
        problem = (
            f"unknown topic {reference.name} in container {place.name}, where {node.name} "
            "is at this point"
        )
    return _in_product(problem, witness)


def _apart(statement: _Statement, client: Any, server: Any) -> str | None:
    """S1: `to server` whose two nodes are in different containers."""
    client_node, server_node = client.eContainer(), server.eContainer()
    for place in statement.names.places(client_node):
        if any(place is p for p in statement.names.places(server_node)):
            conditions = [statement.at(client_node, place), statement.at(server_node, place)]
            if not statement.one_of([c.negated() for c in conditions]):
                return None
    witness = statement.witness()
    if witness is None:
        return None
    client_place = _place(statement, client_node, witness)
    server_place = _place(statement, server_node, witness)
    problem = not_served_here(client, server, [server_place], [client_place])
    return _in_product(f"{problem} (containers at this point)", witness)


def _together(statement: _Statement, client: Any, server: Any) -> str | None:
    """S2: a service bridge whose two nodes are in one container."""
    client_node, server_node = client.eContainer(), server.eContainer()
    options = []
    for place in statement.names.places(client_node):
        if any(place is p for p in statement.names.places(server_node)):
            variable = statement.both(
                statement.at(client_node, place), statement.at(server_node, place)
            )
            if variable is not None:
                options.append(variable)
    if not options:
        return None
    statement.clauses.append(options)
    witness = statement.witness()
    if witness is None:
        return None
    place = _place(statement, client_node, witness)
    return _in_product(same_container_bridge(client, server, place), witness)


def _onto_a_name(statement: _Statement, node: Any, target: Any) -> str | None:
    """N5: a migration into a container holding a node of the same name at that point."""
    options, residents = [], []
    for resident in statement.names.declared.get(node.name, ()):
        if resident is node or not any(target is p for p in statement.names.places(resident)):
            continue
        variable = statement.both(statement.at(resident, target), ALWAYS)
        if variable is not None:
            options.append(variable)
            residents.append(resident)
    if not options:
        return None
    statement.clauses.append(options)
    witness = statement.witness()
    if witness is None:
        return None
    resident = next(r for r in residents if _place(statement, r, witness) is target)
    return _in_product(name_taken(node, target, resident), witness)


def _place(statement: _Statement, node: Any, witness: tuple[str, ...]) -> Any:
    """Where ``node`` is at the statement in the product ``witness``."""
    if statement.names.migrated_here(node):
        return statement.names.places(node)[0]
    selected = set(witness)
    place = node.eContainer()
    for target, element in statement.names.migrations(node):
        if (element.feature.name in selected) == element.activeIfSelected:
            place = target
    return place


def _in_product(problem: str, witness: tuple[str, ...]) -> str:
    return f"{problem}, in the product {', '.join(witness)}"
