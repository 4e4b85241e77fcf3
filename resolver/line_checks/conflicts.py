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
from dataclasses import dataclass
from itertools import combinations
from typing import Any

from spl.diagnostics import Diagnostic, Location, location_of
from spl.dsl.rm_names import Names
from spl.metamodels import tsm
from spl.resolver.context import describe, qualified
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.product_line import ProductLine

CONFLICT = "SPL012"


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
