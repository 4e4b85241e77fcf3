"""SPL052 before any product is chosen: an output no product consumes (an info).

A publisher whose data no subscriber of any product reads costs bandwidth and a bridge
for nothing, or shows a subscriber the model forgot; it is no error, since a tool
outside the architecture (a recorder, a dashboard) may listen. The claim is made only
where it is certain: no template flow from the publisher can hold in a product (its
node and a subscriber's node kept together, :class:`.presence.Presence`), and no
statement can bring a reader to its data: none rebinds the publisher or moves its node,
none binds an interface to or bridges from a topic of the name of one its data reaches,
and none migrates a node into a container holding such a topic (a moved node binds to
a topic of its ROS name there, docs/resolution.md). Anything else may consume it in
some product, and is not reported.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from spl.core.diagnostics import Diagnostic, location_of
from spl.metamodels import interface_kinds
from spl.resolver.architecture.flows import bound_topic, node_of
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.line_checks.presence import Presence
from spl.resolver.resolution.context import qualified
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.transformations import kind_of

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

UNCONSUMED = "SPL052"


def unconsumed_outputs_in_line(line: ProductLine, solver: ActivationSolver) -> list[Diagnostic]:
    """The publishers whose data no subscriber of any product of the line reads."""
    presence = Presence(line, solver)
    names: set[str] = set()  # topic names statements bind interfaces to or bridge from
    touched: set[int] = set()  # publishers rebound, nodes moved, containers moved into
    for element in line.rm.elements:
        for t in element.transformations:
            kind = kind_of(t)
            for binding in kind.rebinds(t):
                touched.add(id(binding.interface))
                names.update([binding.topic] if binding.topic is not None else [])
            names.update(source.name for source, _ in kind.routes(t))
            if (move := kind.move(t)) is not None:
                touched.update((id(move[0]), id(move[1])))
    template = line.template_flows
    reached = line.template_reach
    found = []
    for container in line.tsm.containers:
        for node in container.nodes:
            for interface in node.interfaces:
                topic = bound_topic(interface)
                if not interface_kinds.kind_of(interface).publishes or topic is None:
                    continue
                if {id(interface), id(node)} & touched:
                    continue
                topics = reached[id(topic)]
                if any(t.name in names or id(t.eContainer()) in touched for t in topics):
                    continue
                readers = [f.consumer for f in template.at(interface)]
                if any(_together(presence, solver, node, node_of(r)) for r in readers):
                    continue
                found.append(
                    Diagnostic(
                        location_of(interface),
                        f"{qualified(interface)} publishes {qualified(topic)}, which "
                        "no subscriber of any product reads",
                        "info",
                        UNCONSUMED,
                    )
                )
    return found


def _together(presence: Presence, solver: ActivationSolver, *nodes: tsm_types.Node) -> bool:
    """Whether one product keeps all ``nodes``."""
    clauses: list[list[int]] = []
    for node in nodes:
        keep = presence.present(node)
        if keep is None:
            return False
        clauses += keep
    return not clauses or solver.witness_where(None, clauses) is not None
