"""SPL012: two transformations that can be active in one product and decide one thing
differently (implementation, parameter value, refinement period, migration target, topic,
server, sharing mode); the message names a witness product.

Conflict candidates are found through an index from the decided thing (a node, a
parameter, an interface, ...) to the transformations deciding it, so only pairs that
touch the same thing with different values reach the solver, and each element pair is
asked once.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterator
from itertools import combinations
from typing import TYPE_CHECKING

from spl.core.diagnostics import Diagnostic, location_of
from spl.dsl.rm.names import Names
from spl.metamodels import tsm
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.resolution.context import describe
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.transformations import kind_of, sharing_targets
from spl.resolver.resolution.transformations.kind import Decision, DecisionKey

if TYPE_CHECKING:
    from spl.metamodels import rm_types

CONFLICT = "SPL012"


def decisions(
    element: rm_types.ResolutionElement, names: Names
) -> Iterator[tuple[DecisionKey, Decision]]:
    """Every decision an element takes when active, keyed like the engine's registry
    (kind, decided template element): its statements' (each kind knows its own) and its
    feature's sharing mode. ``names`` follows the elements in file order (a topic named
    without its container is where the node can be at that statement)."""
    names.begin_element(element)
    for t in element.transformations:
        yield from kind_of(t).decisions(t, element, names)
        names.apply(t)
    sharing = element.feature.sharing
    if sharing is not None:
        node_class = tsm().Node
        for node in dict.fromkeys(sharing_targets(element)):  # once each, in order
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
                    f"{', '.join(product or ())}",  # (possible: there is one)
                    "error",
                    CONFLICT,
                )
            )
    return found
