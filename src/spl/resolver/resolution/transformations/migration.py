"""``migrate NODE to CONTAINER``: node migration with endpoint rewiring (docs/semantics.md).

Moving is this kind's whole job. The node's interfaces keep pointing at the topics and
servers they used in the template; the endpoint rewiring (:mod:`spl.resolver.resolution.rewiring`)
runs once after every transformation and rebuilds the cross-container wiring from
those template-level data flows, which keeps the rewiring minimal however many nodes
move and in whatever order.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

from spl.core.diagnostics import location_of
from spl.dsl.rm.messages import name_taken
from spl.resolver.architecture.product import NodeMigration as Moved
from spl.resolver.resolution.context import Cause, ResolutionContext
from spl.resolver.resolution.transformations.kind import (
    Decision,
    DecisionKey,
    Predictions,
    Questions,
    TransformationKind,
)

if TYPE_CHECKING:
    from spl.dsl.rm.names import Names
    from spl.metamodels import rm_types, tsm_types

PLACEMENT = "placement"  # the fleet analysis' aspect: where a node runs


class NodeMigration(TransformationKind["rm_types.NodeMigration"]):
    metaclass = "NodeMigration"

    def apply(self, t: rm_types.NodeMigration, ctx: ResolutionContext) -> None:
        node = ctx.copy_of(t.node)
        target = ctx.copy_of(t.target)
        where = location_of(t)
        ctx.keep(node, f"it is migrated by {ctx.by()}", where)
        # the nodes the copy left out come first, as the template's own before those moved in
        residents = [*ctx.left_out.get(id(target), ()), *target.nodes]
        resident = next((n for n in residents if n.name == node.name and n is not node), None)
        if resident is not None:  # a container's nodes have distinct names (one ROS graph)
            ctx.sink.error(where, name_taken(node, target, resident))
            return
        if not ctx.decide("migration target", node, target.name, where):
            return
        source = node.eContainer()
        target.nodes.append(node)
        ctx.migrations.append(Moved(node.name, source.name, target.name, where))
        moved = f"{node.name} is migrated to {target.name} by {ctx.by()}"
        ctx.displaced[id(node)] = Cause(moved, where)
        ctx.trace.record(
            node.name, "migrated", f"from {source.name} to {target.name} by {ctx.by()}", where
        )

    def touched(self, t: rm_types.NodeMigration) -> Iterator[tsm_types.Node | tsm_types.Store]:
        yield t.node

    def shares(self, t: rm_types.NodeMigration) -> Iterator[tsm_types.Node]:
        yield t.node

    def decisions(
        self, t: rm_types.NodeMigration, element: rm_types.ResolutionElement, names: Names
    ) -> Iterator[tuple[DecisionKey, Decision]]:
        where = location_of(t)
        decision = Decision("migration target", t.node.name, t.target.name, element, where)
        yield ("migration target", id(t.node)), decision

    def predict(
        self, t: rm_types.NodeMigration, element: rm_types.ResolutionElement, effects: Predictions
    ) -> None:
        effects.effect(t.node, PLACEMENT, element, t.target.name, location_of(t))

    def questions(
        self, t: rm_types.NodeMigration, ask: Callable[[], Questions]
    ) -> Iterator[str | None]:
        yield ask().onto_a_name(t.node, t.target)

    def move(self, t: rm_types.NodeMigration) -> tuple[tsm_types.Node, tsm_types.Container]:
        return t.node, t.target
