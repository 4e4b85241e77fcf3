"""``implementation NODE = pkg/executable``: which ROS package and executable run a node."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from spl.diagnostics import location_of
from spl.resolver.context import ResolutionContext, qualified
from spl.resolver.transformations.kind import (
    Decision,
    DecisionKey,
    Predictions,
    TransformationKind,
)


class Implementation(TransformationKind):
    metaclass = "Implementation"

    def apply(self, t: Any, ctx: ResolutionContext) -> None:
        node = ctx.copy_of(t.node)
        value = _value(t)
        where = location_of(t)
        ctx.keep(node, f"its implementation is set by {ctx.by()}", where)
        if ctx.decide("implementation", node, value, where):
            node.package, node.executable = t.package, t.executable
            reason = f"{value}, set by {ctx.by()}"
            ctx.trace.record(qualified(node), "implementation", reason, where)

    def touched(self, t: Any) -> Iterator[Any]:
        yield t.node

    def shares(self, t: Any) -> Iterator[Any]:
        yield t.node

    def decisions(self, t: Any, element: Any, names: Any) -> Iterator[tuple[DecisionKey, Decision]]:
        where = location_of(t)
        decision = Decision("implementation", t.node.name, _value(t), element, where)
        yield ("implementation", id(t.node)), decision

    def predict(self, t: Any, element: Any, effects: Predictions) -> None:
        effects.effect(t.node, "implementation", element, _value(t), location_of(t))


def _value(t: Any) -> str:
    return f"{t.package}/{t.executable}"
