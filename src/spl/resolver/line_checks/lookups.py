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

from collections.abc import Sequence
from functools import partial
from typing import TYPE_CHECKING, NamedTuple, cast

from spl.core.diagnostics import Diagnostic, location_of
from spl.dsl.rm.messages import name_taken, not_served_here, same_container_bridge
from spl.dsl.rm.names import Names, Placement
from spl.resolver.architecture.flows import node_of
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.transformations import kind_of

if TYPE_CHECKING:
    from spl.metamodels import rm_types, tsm_types

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

    def __init__(
        self, solver: ActivationSolver, names: Names, element: rm_types.ResolutionElement
    ) -> None:
        self.solver, self.names, self.element = solver, names, element
        self.clauses: list[list[int]] = []

    def at(self, placement: Placement, place: tsm_types.Container) -> Condition:
        """The node of ``placement`` is in ``place`` at that statement."""
        if placement.certain is not None:
            return ALWAYS if place is placement.certain else NEVER
        literal = self.solver.literal
        if place is placement.node.eContainer():
            return Condition("all", tuple(-literal(e) for _, e in placement.moves))
        return Condition("any", tuple(literal(e) for t, e in placement.moves if t is place))

    def variable(self, condition: Condition) -> int:
        """A new variable implying ``condition``."""
        variable = self.solver.fresh()
        self.clauses += condition.implied_by(variable)
        return variable

    def missing(self, container: tsm_types.Container, name: str) -> Condition | int:
        """Topic ``name`` is missing from ``container`` when the statement runs: a constant,
        or a variable implying it. A `new topic` before created it when its element was
        active and its node was in ``container`` then."""
        if self.names.declared_topic(container, name):
            return NEVER
        not_created: list[list[int]] = []  # per creation: its element off, or its node elsewhere
        for creation in self.names.creations(container, name):
            elsewhere = self.at(creation.placement, container).negated()
            if elsewhere.constant is True:
                continue
            clause = (
                [] if creation.element is self.element else [-self.solver.literal(creation.element)]
            )
            if elsewhere.constant is None:
                clause.append(self.variable(elsewhere))
            if not clause:
                return NEVER  # created by an earlier statement of this element, certainly
            not_created.append(clause)
        if not not_created:
            return ALWAYS
        variable = self.solver.fresh()
        self.clauses += [[-variable, *clause] for clause in not_created]
        return variable

    def one_of(self, options: Sequence[Condition | int]) -> bool:
        """Require that one of ``options`` holds; False when none can."""
        variables = []
        for option in options:
            if isinstance(option, int):
                variables.append(option)
            elif option.constant is True:
                return True
            elif option.constant is None:
                variables.append(self.variable(option))
        if variables:
            self.clauses.append(variables)
        return bool(variables)

    def both(self, first: Condition, second: Condition) -> int | None:
        """A variable implying both conditions, or None when they never hold together."""
        if NEVER in (first, second):
            return None
        variable = self.solver.fresh()
        self.clauses += first.implied_by(variable) + second.implied_by(variable)
        return variable

    def witness(self) -> tuple[str, ...] | None:
        return self.solver.witness_where(self.element, self.clauses)

    # the questions a statement's kind asks (TransformationKind.questions)
    def topic_lookup(
        self, node: tsm_types.Node | None, reference: rm_types.TopicReference
    ) -> str | None:
        return _topic_lookup(self, node, reference)

    def apart(self, client: tsm_types.ServiceClient, server: tsm_types.ServiceServer) -> str | None:
        return _apart(self, client, server)

    def together(
        self, client: tsm_types.ServiceClient, server: tsm_types.ServiceServer
    ) -> str | None:
        return _together(self, client, server)

    def onto_a_name(self, node: tsm_types.Node, target: tsm_types.Container) -> str | None:
        return _onto_a_name(self, node, target)

    def witness_of_any(self, options: list[int]) -> tuple[str, ...] | None:
        """A product where one of ``options`` holds (with the questions asked so far), or
        None when there is none or no option at all."""
        if not options:
            return None
        self.clauses.append(options)
        return self.witness()


def product_dependent_statements(line: ProductLine, solver: ActivationSolver) -> list[Diagnostic]:
    """Statements that fail in some product activating their element (SPL016)."""
    names = Names(line.tsm)
    found = []
    for element in line.rm.elements:
        names.begin_element(element)
        for transformation in element.transformations:
            # one question object per question: each asks the solver once
            asked = partial(_Statement, solver, names, element)
            for problem in kind_of(transformation).questions(transformation, asked):
                if problem is not None:
                    found.append(
                        Diagnostic(location_of(transformation), problem, "error", PRODUCT_DEPENDENT)
                    )
            names.apply(transformation)
    return found


def _topic_lookup(
    statement: _Statement, node: tsm_types.Node | None, reference: rm_types.TopicReference
) -> str | None:
    """O1/T1/T2/T4: the topic named is missing where it is looked up."""
    placement = (
        statement.names.placement(cast("tsm_types.Node", node))  # an unqualified name's
        if reference.container is None
        else None
    )
    named = cast("tsm_types.Container", reference.container)  # when there is no placement
    places = placement.places if placement is not None else [named]
    for place in places:
        elsewhere = statement.at(placement, place).negated() if placement else NEVER
        if not statement.one_of([elsewhere, statement.missing(place, reference.name)]):
            return None  # found there in every product
    witness = statement.witness()
    if witness is None:
        return None
    if placement is None:
        container = cast("tsm_types.Container", reference.container)
        problem = f"unknown topic {reference.name} in container {container.name}"
    else:
        problem = (
            f"unknown topic {reference.name} in container {_place(placement, witness).name}, "
            f"where {placement.node.name} is at this point"
        )
    return _in_product(problem, witness)


def _common_places(
    statement: _Statement, client: tsm_types.ServiceClient, server: tsm_types.ServiceServer
) -> tuple[list[Placement], list[tsm_types.Container]]:
    """The placements of two interfaces' nodes and the containers both can be in."""
    placements = [statement.names.placement(node_of(i)) for i in (client, server)]
    common = [p for p in placements[0].places if any(p is q for q in placements[1].places)]
    return placements, common


def _apart(
    statement: _Statement, client: tsm_types.ServiceClient, server: tsm_types.ServiceServer
) -> str | None:
    """S1: `to server` whose two nodes are in different containers."""
    placements, common = _common_places(statement, client, server)
    for place in common:
        conditions = [statement.at(p, place).negated() for p in placements]
        if not statement.one_of(conditions):
            return None
    witness = statement.witness()
    if witness is None:
        return None
    client_place, server_place = (_place(p, witness) for p in placements)
    problem = not_served_here(client, server, [server_place], [client_place])
    return _in_product(f"{problem} (containers at this point)", witness)


def _together(
    statement: _Statement, client: tsm_types.ServiceClient, server: tsm_types.ServiceServer
) -> str | None:
    """S2: a service bridge whose two nodes are in one container."""
    placements, common = _common_places(statement, client, server)
    options = [statement.both(*(statement.at(p, place) for p in placements)) for place in common]
    witness = statement.witness_of_any([v for v in options if v is not None])
    if witness is None:
        return None
    place = _place(placements[0], witness)
    return _in_product(same_container_bridge(client, server, place), witness)


def _onto_a_name(
    statement: _Statement, node: tsm_types.Node, target: tsm_types.Container
) -> str | None:
    """N5: a migration into a container holding a node of the same name at that point."""
    residents = [
        statement.names.placement(cast("tsm_types.Node", r))  # (a store is placed alike)
        for r in statement.names.declared.get(node.name, ())
        if r is not node
    ]
    residents = [p for p in residents if any(target is c for c in p.places)]
    witness = statement.witness_of_any(
        [statement.variable(statement.at(p, target)) for p in residents]
    )
    if witness is None:
        return None
    resident = next(p.node for p in residents if _place(p, witness) is target)
    return _in_product(name_taken(node, target, resident), witness)


def _place(placement: Placement, witness: tuple[str, ...]) -> tsm_types.Container:
    """Where the node of ``placement`` is in the product ``witness``: moved by the first
    active migration before the statement (a later one elsewhere is a conflict, SPL012,
    and is not applied)."""
    if placement.certain is not None:
        return placement.certain
    selected = set(witness)
    for target, element in placement.moves:
        if (element.feature.name in selected) == element.activeIfSelected:
            return target
    return placement.node.eContainer()


def _in_product(problem: str, witness: tuple[str, ...]) -> str:
    return f"{problem}, in the product {', '.join(witness)}"
