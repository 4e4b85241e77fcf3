"""Parameter transformation: a node parameter set to a literal or a feature attribute."""

from __future__ import annotations

from typing import Any

from spl.diagnostics import location_of
from spl.resolver.context import ResolutionContext, qualified


def canonical_text(value: Any, parameter_type: str) -> str:
    """A product attribute value written the way the .tsm writes parameter values."""
    if parameter_type == "bool":
        return "true" if value else "false"
    if parameter_type == "double":
        return repr(float(value))
    if parameter_type == "int":
        return str(int(value))
    return str(value)


def apply(transformation: Any, ctx: ResolutionContext) -> None:
    parameter = ctx.copy_of(transformation.parameter)
    node = parameter.eContainer()
    where = location_of(transformation)
    attribute = transformation.attribute
    if attribute is not None:
        key = f"{attribute.eContainer().name}.{attribute.name}"
        value = canonical_text(ctx.attributes[key], parameter.type.name)
        source = f"feature attribute {key} = {value}"
    else:
        value, source = transformation.value, f"{transformation.value!r}"
    ctx.keep(node, f"its parameter {parameter.name} is set by {ctx.by()}", where)
    if ctx.decide("value", parameter, value, where):
        parameter.value = value
        ctx.trace.record(qualified(parameter), "parameter", f"{source}, set by {ctx.by()}", where)
