"""``parameter NODE.P = value | feature F.a`` (and a store refinement's ``period``)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from spl.diagnostics import location_of
from spl.dsl import literals
from spl.dsl.tsm_data import period_fits
from spl.resolver.context import ResolutionContext, qualified
from spl.resolver.transformations.kind import (
    Decision,
    DecisionKey,
    Predictions,
    TransformationKind,
)


def canonical_text(value: Any, parameter_type: str) -> str:
    """A product attribute value written the way the .tsm writes parameter values."""
    if parameter_type == "bool":
        return "true" if value else "false"
    if parameter_type == "double":
        return repr(float(value))
    if parameter_type == "int":
        return str(int(value))
    return str(value)


class ParameterValue(TransformationKind):
    metaclass = "ParameterValue"

    def apply(self, t: Any, ctx: ResolutionContext) -> None:
        where = location_of(t)
        if t.refinement is not None:
            _set_period(t, ctx, where)
            return
        parameter = ctx.copy_of(t.parameter)
        node = parameter.eContainer()
        value, source = _value(t, ctx, parameter.type.name)
        if parameter.type.name == "int" and abs(int(value)) > literals.ROS_INT_MAX:
            ctx.sink.error(
                where,
                f"parameter {node.name}.{parameter.name} cannot be {source}: "
                f"{literals.ROS_INT_RANGE}",
            )
            return
        ctx.keep(node, f"its parameter {parameter.name} is set by {ctx.by()}", where)
        if ctx.decide("value", parameter, value, where):
            parameter.value = value
            ctx.trace.record(
                qualified(parameter), "parameter", f"{source}, set by {ctx.by()}", where
            )

    def touched(self, t: Any) -> Iterator[Any]:
        owner = t.refinement if t.refinement is not None else t.parameter
        yield owner.eContainer()

    def decisions(self, t: Any, element: Any, names: Any) -> Iterator[tuple[DecisionKey, Decision]]:
        where = location_of(t)
        value = (
            f"feature {t.attribute.eContainer().name}.{t.attribute.name}"
            if t.attribute is not None
            else repr(t.value)
        )
        if t.refinement is not None:
            store = t.refinement.eContainer()
            subject = f"{store.name}.{t.refinement.output.name}.period"
            yield ("period", id(t.refinement)), Decision("period", subject, value, element, where)
        else:
            decision = Decision("value", qualified(t.parameter), value, element, where)
            yield ("value", id(t.parameter)), decision

    def predict(self, t: Any, element: Any, effects: Predictions) -> None:
        if t.parameter is None:
            return  # a refinement's period: no node's aspect
        value = t.value if t.attribute is None else _attribute_value(t)
        aspect = f"parameter {t.parameter.name}"
        effects.effect(t.parameter.eContainer(), aspect, element, value, location_of(t))

    def attribute(self, t: Any) -> Any:
        return t.attribute


def _attribute_value(t: Any) -> Any:
    """A parameter set from a feature attribute: the robot's value, else the default,
    written as the engine writes it."""
    attribute = t.attribute
    key = f"{attribute.eContainer().name}.{attribute.name}"
    kind = t.parameter.type.name
    default = attribute.value

    def value(settings: Any) -> str:
        given = dict(settings.attributes)
        if key in given:
            return canonical_text(given[key], kind)
        typed = {"int": int, "double": float, "bool": lambda text: text == "true"}.get(
            attribute.type.name, str
        )(default)
        return canonical_text(typed, kind)

    return value


def _value(t: Any, ctx: ResolutionContext, kind: str) -> tuple[str, str]:
    attribute = t.attribute
    if attribute is None:
        return t.value, repr(t.value)
    key = f"{attribute.eContainer().name}.{attribute.name}"
    value = canonical_text(ctx.attributes[key], kind)
    return value, f"feature attribute {key} = {value}"


def _set_period(t: Any, ctx: ResolutionContext, where: Any) -> None:
    """The transformer period of a store's refinement (seconds)."""
    refinement = ctx.copy_of(t.refinement)
    store = refinement.eContainer()
    value, source = _value(t, ctx, "double")
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
