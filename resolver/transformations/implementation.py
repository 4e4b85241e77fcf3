"""Implementation transformation: which ROS package and executable run a node."""

from __future__ import annotations

from typing import Any

from spl.diagnostics import location_of
from spl.resolver.context import ResolutionContext, qualified


def apply(transformation: Any, ctx: ResolutionContext) -> None:
    node = ctx.copy_of(transformation.node)
    value = f"{transformation.package}/{transformation.executable}"
    where = location_of(transformation)
    ctx.keep(node, f"its implementation is set by {ctx.by()}", where)
    if ctx.decide("implementation", node, value, where):
        node.package, node.executable = transformation.package, transformation.executable
        ctx.trace.record(qualified(node), "implementation", f"{value}, set by {ctx.by()}", where)
