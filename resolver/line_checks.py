"""Checks of a product line as a whole (SPEC section 8), before any product is derived.

The engine finds a conflict only in the one product it resolves; a CI job wants to
know that *no* product of the line can hit one, without deriving them all. Each check
here asks the SAT solver about the activation literals of resolution elements
(``F`` for ``when F selected``, ``-F`` for ``when F not selected``) under assumptions,
so the cost grows with the number of elements and of candidate pairs, never with the
number of products:

========  ========  ==================================================================
code      severity  finding
========  ========  ==================================================================
SPL010    error     a resolution element that can never be active (its feature is dead,
                    or core for ``not selected``), with the feature-model rules why
SPL011    warning   an optional node or store no product can contain: no element that
                    can be active requires or transforms it
SPL012    error     two transformations of elements that can be active in one product
                    decide one thing differently (implementation, parameter value,
                    refinement period, migration target, topic, server, sharing mode);
                    the message names a witness product
SPL013    error     a migration to a missing container or to the node's own container
                    (found by the .rm parser, ``spl.dsl.rm.MIGRATION_TARGET``, so
                    ``spl check DIR`` reports it on parsing)
SPL014    info      a concrete leaf feature with no effect: no resolution element,
                    attribute, sharing mode or constraint mentions it
SPL015    warning   a listed product (``products/*.yaml``) that is not a valid, complete
                    selection
SPL016    error     a statement that fails in some product activating its element: a
                    topic missing where the node is at that point, a client and server
                    apart, ... (:mod:`spl.resolver.lookup_checks`, docs/semantics.md C3);
                    the message names a witness product
========  ========  ==================================================================

Conflict candidates are found through an index from the decided thing (a node, a
parameter, an interface, ...) to the transformations deciding it, so only pairs that
touch the same thing with different values reach the solver, and each element pair is
asked once.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterator
from dataclasses import dataclass
from itertools import combinations
from typing import Any

from spl.diagnostics import Diagnostic, Location, ModelError, location_of
from spl.dsl.rm_names import Names
from spl.metamodels import tsm
from spl.resolver.activation import ActivationSolver
from spl.resolver.context import describe, qualified
from spl.resolver.lookup_checks import product_dependent_statements
from spl.resolver.product_line import ProductLine
from spl.resolver.selection import check_selection

DEAD_ELEMENT = "SPL010"
UNREACHABLE_OPTIONAL = "SPL011"
CONFLICT = "SPL012"
NO_EFFECT = "SPL014"
UNRESOLVABLE_PRODUCT = "SPL015"


# --- SPL010 --------------------------------------------------------------------------


def never_active_elements(line: ProductLine, solver: ActivationSolver) -> list[Diagnostic]:
    """Elements no product activates: dead code in the resolution model."""
    solver.decide(list(line.rm.elements))
    found = []
    for element in line.rm.elements:
        if solver.possible(element):
            continue
        name = element.feature.name
        if element.activeIfSelected:
            check = check_selection(line.formula, [name])
            state, why = "selected", f"feature {name} is dead (in no product)"
        else:
            check = check_selection(line.formula, [], [name])
            state, why = "not selected", f"feature {name} is core (in every product)"
        reason = check.explanation()
        found.append(
            Diagnostic(
                location_of(element),
                f"resolution element 'when {name} {state}' can never be active: {why}"
                + (f", because {reason}" if reason else ""),
                "error",
                DEAD_ELEMENT,
            )
        )
    return found


# --- SPL011 --------------------------------------------------------------------------


def touched_elements(element: Any) -> Iterator[Any]:
    """The nodes and stores a resolution element keeps in a product when it is active
    (what the engine's ``keep`` is called with)."""
    yield from element.required
    for t in element.transformations:
        kind = t.eClass.name
        if kind in ("Implementation", "NodeMigration"):
            yield t.node
        elif kind in ("ConnectToTopic", "ConnectToNewTopic"):
            yield t.interface.eContainer()
        elif kind == "ConnectService" or (kind == "ConnectBridge" and t.client is not None):
            yield t.client.eContainer()
            yield t.server.eContainer()
        elif kind == "ParameterValue":
            owner = t.refinement if t.refinement is not None else t.parameter
            yield owner.eContainer()


def unreachable_optional_elements(line: ProductLine, solver: ActivationSolver) -> list[Diagnostic]:
    """Optional nodes and stores that only enter a product through an active element."""
    reachable: set[int] = set()
    mentioned: set[int] = set()
    for element in line.rm.elements:
        touched = [id(x) for x in touched_elements(element)]
        mentioned.update(touched)
        if solver.possible(element):
            reachable.update(touched)
    found = []
    for container in line.tsm.containers:
        for what, members in (("node", container.nodes), ("store", container.stores)):
            for member in members:
                if not member.optional or id(member) in reachable:
                    continue
                why = (
                    "only resolution elements that can never be active require or transform it"
                    if id(member) in mentioned
                    else "no resolution element requires or transforms it"
                )
                found.append(
                    Diagnostic(
                        location_of(member),
                        f"optional {what} {container.name}.{member.name} is in no product: {why}",
                        "warning",
                        UNREACHABLE_OPTIONAL,
                    )
                )
    return found


# --- SPL012 --------------------------------------------------------------------------


@dataclass(frozen=True)
class Decision:
    """What one transformation (or a feature's sharing mode) decides about one thing."""

    kind: str  # the engine's wording: implementation, value, period, migration target, ...
    subject: str  # the thing decided, as messages name it
    value: str
    element: Any  # the resolution element deciding
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


def decisions(element: Any, names: Names) -> Iterator[tuple[tuple[str, int], Decision]]:
    """Every decision an element takes when active, keyed like the engine's registry
    (kind, decided template element). ``names`` follows the elements in file order (a
    topic named without its container is where the node can be at that statement)."""
    names.begin_element(element)
    for t in element.transformations:
        where = location_of(t)
        kind = t.eClass.name
        if kind == "Implementation":
            value = f"{t.package}/{t.executable}"
            yield (
                ("implementation", id(t.node)),
                Decision("implementation", t.node.name, value, element, where),
            )
        elif kind == "NodeMigration":
            yield (
                ("migration target", id(t.node)),
                Decision("migration target", t.node.name, t.target.name, element, where),
            )
        elif kind == "ParameterValue":
            value = (
                f"feature {t.attribute.eContainer().name}.{t.attribute.name}"
                if t.attribute is not None
                else repr(t.value)
            )
            if t.refinement is not None:
                store = t.refinement.eContainer()
                subject = f"{store.name}.{t.refinement.output.name}.period"
                yield (
                    ("period", id(t.refinement)),
                    Decision("period", subject, value, element, where),
                )
            else:
                yield (
                    ("value", id(t.parameter)),
                    Decision("value", qualified(t.parameter), value, element, where),
                )
        elif kind in ("ConnectToTopic", "ConnectToNewTopic"):
            # a topic is identified by its container and name (a `new topic` declared by
            # two elements is one topic)
            container = getattr(t.topic, "container", None)
            places = names.places(t.interface.eContainer())
            if container is None and len(places) == 1:
                container = places[0]
            name = t.topic.name
            topic = (container.name if container is not None else None, name)
            yield (
                ("topic", id(t.interface)),
                Decision(
                    "topic",
                    qualified(t.interface),
                    f"{container.name}.{name}" if container is not None else name,
                    element,
                    where,
                    topic,
                ),
            )
        elif kind == "ConnectService" or (kind == "ConnectBridge" and t.client is not None):
            server = t.server
            value = f"{server.eContainer().eContainer().name}.{qualified(server)}"
            yield (
                ("server", id(t.client)),
                Decision("server", qualified(t.client), value, element, where),
            )
        names.apply(t)
    sharing = element.feature.sharing
    if sharing is not None:
        node_class = tsm().Node
        targets = list(element.required) + [
            t.node
            for t in element.transformations
            if t.eClass.name in ("Implementation", "NodeMigration")
        ]
        for node in dict.fromkeys(targets):  # once each, in order
            if isinstance(node, node_class):
                yield (
                    ("sharing mode", id(node)),
                    Decision(
                        "sharing mode",
                        node.name,
                        f"{sharing.mode.name} (default of feature {element.feature.name})",
                        element,
                        location_of(element),
                    ),
                )


def reachable_conflicts(line: ProductLine, solver: ActivationSolver) -> list[Diagnostic]:
    """Pairs of decisions that disagree and whose elements are active in one product."""
    index: dict[tuple[str, int], list[Decision]] = defaultdict(list)
    names = Names(line.tsm)
    for element in line.rm.elements:
        for key, decision in decisions(element, names):
            index[key].append(decision)
    found = []
    for key, taken in index.items():
        if len({d.value for d in taken}) < 2:
            continue
        for first, second in combinations(taken, 2):
            if not first.differs(second):
                continue
            if not solver.possible(first.element, second.element):
                continue
            product = solver.witness(first.element, second.element)
            found.append(
                Diagnostic(
                    second.location,
                    f"conflict: {describe(second.element)} gives {key[0]} {second.value} to "
                    f"{second.subject}, but {describe(first.element)} gives {first.value} "
                    f"(at {first.location}); both are active in the product "
                    f"{', '.join(product)}",
                    "error",
                    CONFLICT,
                )
            )
    return found


# --- SPL014 --------------------------------------------------------------------------


def _features(feature: Any) -> Iterator[Any]:
    yield feature
    for group in feature.groups:
        for child in group.features:
            yield from _features(child)


def _formula_features(formula: Any) -> Iterator[Any]:
    if formula is None:
        return
    if formula.eClass.name == "FeatureRef":
        yield formula.feature
        return
    for reference in formula.eClass.eAllReferences():
        if reference.containment:
            yield from _formula_features(formula.eGet(reference))


def features_without_effect(line: ProductLine) -> list[Diagnostic]:
    """Concrete leaves that nothing reads: choosing them changes no product's architecture,
    attributes or sharing, and they constrain no other feature."""
    mentioned: set[str] = set()
    not_selected: set[str] = set()
    for element in line.rm.elements:
        mentioned.add(element.feature.name)
        if not element.activeIfSelected:
            not_selected.add(element.feature.name)
        for t in element.transformations:
            if t.eClass.name == "ParameterValue" and t.attribute is not None:
                mentioned.add(t.attribute.eContainer().name)
    for constraint in line.fm.constraints:
        mentioned.update(f.name for f in _formula_features(constraint.formula))
    found = []
    for feature in _features(line.fm.root):
        if (
            feature.name in mentioned
            or feature.abstract
            or feature.groups
            or feature.attributes
            or feature.sharing is not None
        ):
            continue
        group = feature.eContainer()
        # in an alternative group, choosing this feature deselects its siblings: when a
        # sibling has a `not selected` element, the choice matters
        if group is not None and group.eClass.name == "Group":
            siblings = {f.name for f in group.features if f is not feature}
            if group.kind.name == "alternative" and siblings & not_selected:
                continue
        found.append(
            Diagnostic(
                location_of(feature),
                f"feature {feature.name} has no effect: no resolution element, attribute, "
                "sharing mode or constraint mentions it",
                "info",
                NO_EFFECT,
            )
        )
    return found


# --- SPL015 --------------------------------------------------------------------------


def unresolvable_products(line: ProductLine) -> list[Diagnostic]:
    """Listed products that are not a valid, complete selection of the feature model."""
    from spl.resolver.product_selection import load_selection_file

    found = []
    for path in line.product_files():
        try:
            selection = load_selection_file(path)
            check = check_selection(
                line.formula,
                selection.features,
                selection.deselected,
                selection.locations,
                Location(str(path), 1, 1),
            )
        except ModelError as exc:
            found.extend(_as_warnings(exc.diagnostics, f"product {path.stem}: "))
            continue
        if check.status == "invalid":  # located at the selected feature that contradicts
            found.extend(
                _as_warnings(
                    [d for d in check.diagnostics if d.severity == "error"],
                    f"product {selection.name} does not resolve: ",
                )
            )
        elif check.status == "incomplete":
            found.append(
                Diagnostic(
                    Location(str(path), 1, 1),
                    f"product {selection.name} does not resolve: open choice: "
                    f"{check.explanation()}",
                    "warning",
                    UNRESOLVABLE_PRODUCT,
                )
            )
    return found


def _as_warnings(diagnostics: list[Diagnostic], prefix: str) -> list[Diagnostic]:
    return [
        Diagnostic(d.location, prefix + d.message, "warning", UNRESOLVABLE_PRODUCT)
        for d in diagnostics
    ]


# --- all -----------------------------------------------------------------------------


def check_product_line(line: ProductLine, products: bool = True) -> list[Diagnostic]:
    """Every line check, sorted by location; ``products`` includes the listed products."""
    with ActivationSolver(line) as solver:
        found = never_active_elements(line, solver)
        found += unreachable_optional_elements(line, solver)
        found += reachable_conflicts(line, solver)
        found += product_dependent_statements(line, solver)
    found += features_without_effect(line)
    if products:
        found += unresolvable_products(line)
    return sorted(found, key=diagnostic_order)


def diagnostic_order(d: Diagnostic) -> tuple:
    loc = d.location or Location("")
    return (loc.file, loc.line, loc.col, d.code or "", d.message)
