"""Which products keep a template node, as clauses over activation literals.

An optional node enters a product only through an active resolution element that
requires or transforms it (:func:`spl.resolver.resolution.transformations.touched_elements`, what
the engine keeps, docs/resolution.md step 5); any other node is in every product. The
line checks that follow data from node to node (:mod:`.cross_robot`,
:mod:`.dataflow`) ask the solver about these clauses, so both read one encoding of
pruning, the engine's own.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.resolution.product_line import ProductLine

if TYPE_CHECKING:
    from spl.metamodels import rm_types, tsm_types

Clauses = list[list[int]]


class Presence:
    """The elements keeping each optional node, and the clauses saying a node is in a
    product or not."""

    def __init__(self, line: ProductLine, solver: ActivationSolver) -> None:
        self.keeping = line.node_keepers
        self.solver = solver

    def keepers(self, node: tsm_types.Node) -> list[rm_types.ResolutionElement]:
        """The resolution elements that keep ``node`` when active (none for a node that
        is not optional: it needs none)."""
        return self.keeping.get(id(node), []) if node.optional else []

    def present(self, node: tsm_types.Node) -> Clauses | None:
        """Clauses keeping ``node`` in a product; None when no product can."""
        if not node.optional:
            return []
        literals = [self.solver.literal(e) for e in self.keepers(node)]
        return [literals] if literals else None

    def absent(self, node: tsm_types.Node) -> Clauses | None:
        """Clauses leaving ``node`` out of a product; None when every product keeps it."""
        if not node.optional:
            return None
        return [[-self.solver.literal(e)] for e in self.keepers(node)]
