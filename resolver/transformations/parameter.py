"""Parameter transformation: a node parameter set to a literal or a feature attribute."""

from __future__ import annotations

from typing import Any

from spl.diagnostics import location_of
from spl.dsl import literals
from spl.dsl.tsm_data import period_fits
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
    where = location_of(transformation)
    if transformation.refinement is not None:
        _set_period(transformation, ctx, where)
        return
    parameter = ctx.copy_of(transformation.parameter)
    node = parameter.eContainer()
    value, source = _value(transformation, ctx, parameter.type.name)
    if parameter.type.name == "int" and abs(int(value)) > literals.ROS_INT_MAX:
        ctx.sink.error(
            where,
            f"parameter {node.name}.{parameter.name} cannot be {source}: {literals.ROS_INT_RANGE}",
        )
        return
    ctx.keep(node, f"its parameter {parameter.name} is set by {ctx.by()}", where)
    if ctx.decide("value", parameter, value, where):
        parameter.value = value
        ctx.trace.record(qualified(parameter), "parameter", f"{source}, set by {ctx.by()}", where)


def _value(transformation: Any, ctx: ResolutionContext, kind: str) -> tuple[str, str]:
    attribute = transformation.attribute
    if attribute is None:
        return transformation.value, repr(transformation.value)
    key = f"{attribute.eContainer().name}.{attribute.name}"
    value = canonical_text(ctx.attributes[key], kind)
    return value, f"feature attribute {key} = {value}"


def _set_period(transformation: Any, ctx: ResolutionContext, where) -> None:
    """The transformer period of a store's refinement (seconds)."""
    refinement = ctx.copy_of(transformation.refinement)
    store = refinement.eContainer()
    value, source = _value(transformation, ctx, "double")
    if not period_fits(float(value)):  # an attribute's value; a literal was checked by the .rm
        ctx.sink.error(
            where,
            f"the transformer period of {store.name}.{refinement.output.name} cannot be "
            f"{source} s: it must be positive and at most a year",
        )
        return
    ctx.keep(store, f"its transformer period is set by {ctx.by()}", where)
    if ctx.decide("period", refinement, value, where):
        refinement.period = float(value)
        ctx.trace.record(
            f"{qualified(store)}.{refinement.output.name}",
            "period",
            f"{source} s, set by {ctx.by()}",
            where,
        )
