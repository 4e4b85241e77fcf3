"""``parameter NODE.P = value | feature F.a`` (and a store refinement's ``period``)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Location, location_of
from spl.dsl import literals
from spl.dsl.tsm.data import PERIOD_RANGE, period_fits
from spl.resolver.architecture.product import AttributeValue
from spl.resolver.resolution.context import ResolutionContext, qualified, subject_name
from spl.resolver.resolution.transformations.kind import (
    Decision,
    DecisionKey,
    Predictions,
    TransformationKind,
)

if TYPE_CHECKING:
    from spl.dsl.rm.names import Names
    from spl.metamodels import fm_types, rm_types, tsm_types
    from spl.resolver.resolution.effects import Settings


def canonical_text(value: AttributeValue, parameter_type: str) -> str:
    """A product attribute value written the way the .tsm writes parameter values."""
    if parameter_type == "bool":
        return "true" if value else "false"
    if parameter_type == "double":
        return repr(float(value))  # type: ignore[arg-type]  # a number (checked by type)
    if parameter_type == "int":
        return str(int(value))  # type: ignore[arg-type]
    return str(value)


class ParameterValue(TransformationKind["rm_types.ParameterValue"]):
    metaclass = "ParameterValue"

    def apply(self, t: rm_types.ParameterValue, ctx: ResolutionContext) -> None:
        where = location_of(t)
        if t.refinement is not None:
            _set_period(t, ctx, where)
            return
        parameter = ctx.copy_of(cast("tsm_types.Parameter", t.parameter))  # or a refinement
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

    def touched(self, t: rm_types.ParameterValue) -> Iterator[tsm_types.Node | tsm_types.Store]:
        if t.refinement is not None:
            yield t.refinement.eContainer()
        else:
            yield cast("tsm_types.Parameter", t.parameter).eContainer()

    def decisions(
        self, t: rm_types.ParameterValue, element: rm_types.ResolutionElement, names: Names
    ) -> Iterator[tuple[DecisionKey, Decision]]:
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
            parameter = cast("tsm_types.Parameter", t.parameter)  # when no refinement
            decision = Decision("value", qualified(parameter), value, element, where)
            yield ("value", id(t.parameter)), decision

    def predict(
        self, t: rm_types.ParameterValue, element: rm_types.ResolutionElement, effects: Predictions
    ) -> None:
        if t.parameter is None:
            return  # a refinement's period: no node's aspect
        value = t.value if t.attribute is None else _attribute_value(t)
        aspect = f"parameter {t.parameter.name}"
        effects.effect(t.parameter.eContainer(), aspect, element, value, location_of(t))

    def attribute(self, t: rm_types.ParameterValue) -> fm_types.Attribute | None:
        return t.attribute


def _attribute_value(t: rm_types.ParameterValue) -> Callable[[Settings], str]:
    """A parameter set from a feature attribute: the robot's value, else the default,
    written as the engine writes it."""
    attribute = cast("fm_types.Attribute", t.attribute)  # called when it is set
    key = f"{attribute.eContainer().name}.{attribute.name}"
    kind = cast("tsm_types.Parameter", t.parameter).type.name
    default = attribute.value

    def value(settings: Settings) -> str:
        given = dict(settings.attributes)
        if key in given:
            return canonical_text(given[key], kind)
        read: dict[str, Callable[[str], AttributeValue]] = {
            "int": int,
            "double": float,
            "bool": lambda text: text == "true",
        }
        typed = read.get(attribute.type.name, str)(default)
        return canonical_text(typed, kind)

    return value


def _value(t: rm_types.ParameterValue, ctx: ResolutionContext, kind: str) -> tuple[str, str]:
    attribute = t.attribute
    if attribute is None:
        return t.value, repr(t.value)
    key = f"{attribute.eContainer().name}.{attribute.name}"
    value = canonical_text(ctx.attributes[key], kind)
    return value, f"feature attribute {key} = {value}"


def _set_period(t: rm_types.ParameterValue, ctx: ResolutionContext, where: Location | None) -> None:
    """The transformer period of a store's refinement (seconds)."""
    refinement = ctx.copy_of(cast("tsm_types.Refinement", t.refinement))
    store = refinement.eContainer()
    value, source = _value(t, ctx, "double")
    if not period_fits(float(value)):  # an attribute's value; a literal was checked by the .rm
        ctx.sink.error(
            where,
            f"the transformer period of {store.name}.{refinement.output.name} cannot be "
            f"{source} s: it must be {PERIOD_RANGE}",
        )
        return
    ctx.keep(store, f"its transformer period is set by {ctx.by()}", where)
    if ctx.decide("period", refinement, value, where):
        refinement.period = float(value)
        ctx.trace.record(
            subject_name(refinement),
            "period",
            f"{source} s, set by {ctx.by()}",
            where,
        )
