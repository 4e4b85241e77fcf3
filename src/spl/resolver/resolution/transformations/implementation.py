"""``implementation NODE = pkg/executable [args "..."]``: which ROS package and executable
run a node, and with which arguments. The arguments are a decision of their own: a
statement without ``args`` keeps the node's, and decides nothing about them (docs/rm.md)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from typing import TYPE_CHECKING

from spl.core.diagnostics import location_of
from spl.resolver.resolution.context import ResolutionContext, qualified
from spl.resolver.resolution.transformations.kind import (
    Decision,
    DecisionKey,
    Predictions,
    TransformationKind,
)

if TYPE_CHECKING:
    from spl.dsl.rm.names import Names
    from spl.metamodels import rm_types, tsm_types


class Implementation(TransformationKind["rm_types.Implementation"]):
    metaclass = "Implementation"

    def apply(self, t: rm_types.Implementation, ctx: ResolutionContext) -> None:
        node = ctx.copy_of(t.node)
        value = _value(t)
        where = location_of(t)
        ctx.keep(node, f"its implementation is set by {ctx.by()}", where)
        if ctx.decide("implementation", node, value, where):
            node.package, node.executable = t.package, t.executable
            reason = f"{value}, set by {ctx.by()}"
            ctx.trace.record(qualified(node), "implementation", reason, where)
        if t.args is not None and ctx.decide("args", node, _shown(t.args), where):
            node.args = t.args
            reason = f"{_shown(t.args)}, set by {ctx.by()}"
            ctx.trace.record(qualified(node), "args", reason, where)

    def touched(self, t: rm_types.Implementation) -> Iterator[tsm_types.Node | tsm_types.Store]:
        yield t.node

    def shares(self, t: rm_types.Implementation) -> Iterator[tsm_types.Node]:
        yield t.node

    def decisions(
        self, t: rm_types.Implementation, element: rm_types.ResolutionElement, names: Names
    ) -> Iterator[tuple[DecisionKey, Decision]]:
        where = location_of(t)
        decision = Decision("implementation", t.node.name, _value(t), element, where)
        yield ("implementation", id(t.node)), decision
        if t.args is not None:
            args = Decision("args", t.node.name, _shown(t.args), element, where)
            yield ("args", id(t.node)), args

    def predict(
        self, t: rm_types.Implementation, element: rm_types.ResolutionElement, effects: Predictions
    ) -> None:
        where = location_of(t)
        effects.effect(t.node, "implementation", element, _value(t), where)
        if t.args is not None:
            effects.effect(t.node, "args", element, t.args, where)


def _value(t: rm_types.Implementation) -> str:
    return f"{t.package}/{t.executable}"


def _shown(args: str) -> str:
    """Arguments as the statement writes them (blanks in them, or none at all)."""
    return json.dumps(args)
