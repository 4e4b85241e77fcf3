"""Node migration: move a node to another container (SPEC 5.3).

Moving is this function's whole job. The node's interfaces keep pointing at the
topics and servers they used in the template; the endpoint rewiring
(:mod:`spl.resolver.rewiring`) runs once after every transformation and rebuilds the
cross-container wiring from those template-level data flows, which keeps the rewiring
minimal however many nodes move and in whatever order.
"""

from __future__ import annotations

from typing import Any

from spl.diagnostics import location_of
from spl.dsl.rm_names import name_taken
from spl.resolver.context import Cause, ResolutionContext
from spl.resolver.product import NodeMigration


def apply(transformation: Any, ctx: ResolutionContext) -> None:
    node = ctx.copy_of(transformation.node)
    target = ctx.copy_of(transformation.target)
    where = location_of(transformation)
    ctx.keep(node, f"it is migrated by {ctx.by()}", where)
    resident = next((n for n in target.nodes if n.name == node.name and n is not node), None)
    if resident is not None:  # a container's nodes have distinct names (one ROS graph)
        ctx.sink.error(where, name_taken(node, target, resident))
        return
    if not ctx.decide("migration target", node, target.name, where):
        return
    source = node.eContainer()
    target.nodes.append(node)
    ctx.migrations.append(NodeMigration(node.name, source.name, target.name, where))
    moved = f"{node.name} is migrated to {target.name} by {ctx.by()}"
    ctx.displaced[id(node)] = Cause(moved, where)
    ctx.trace.record(
        node.name, "migrated", f"from {source.name} to {target.name} by {ctx.by()}", where
    )
