"""The Resolution Engine: one product's architecture from the product line
(docs/resolution.md).

Each step is a function over the model; this module only runs them in order:
selection checked and completed (SAT), template copied, active resolution elements
applied in file order (one module per transformation kind), sharing modes, pruning,
endpoint rewiring, architecture checks.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, cast

from spl.core.cyclic_gc import release, without_cyclic_gc
from spl.core.diagnostics import DiagnosticSink, Location, ModelError, location_of
from spl.dsl import literals
from spl.metamodels import tsm
from spl.resolver.architecture.checks import (
    check_architecture,
    shared_across_users,
    unlinked_clouds,
)
from spl.resolver.architecture.flows import FlowTable
from spl.resolver.architecture.product import AttributeValue, ResolvedProduct, node_keys
from spl.resolver.architecture.wiring import cross_robot_flows
from spl.resolver.resolution import pruning, rewiring
from spl.resolver.resolution.capabilities import CapabilityChoice, choose_features, merge_choices
from spl.resolver.resolution.context import ResolutionContext, describe
from spl.resolver.resolution.data_clients import implement_data_clients
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.product_selection import CommandLineValue, ProductSelection, typed_text
from spl.resolver.resolution.selection import SelectionCheck, check_selection
from spl.resolver.resolution.trace import Trace
from spl.resolver.resolution.transformations import kind_of, sharing_targets

if TYPE_CHECKING:
    from spl.metamodels import fm_types, rm_types, tsm_types
    from spl.metamodels.model_types import EObject


@dataclass
class Resolution:
    product: ResolvedProduct
    trace: Trace
    completion: SelectionCheck
    removed_nodes: tuple[str, ...]
    kept_nodes: tuple[str, ...]
    capability_choices: tuple[CapabilityChoice, ...] = ()
    # the template's elements by id -> theirs in the product, for release()
    copies: dict[int, EObject] = field(default_factory=dict, repr=False, compare=False)

    def release(self) -> None:
        """Frees the product's model now: for a caller done with it (a witness product
        of the line checks, once its warnings are read), which must not read it again."""
        release(self.copies.values())
        self.copies.clear()


def resolve(line: ProductLine, selection: ProductSelection) -> Resolution:
    # resolution builds one large graph and keeps it all: the collector rescanning it
    # while it grows made resolve time superlinear; its cycles are left for later
    # (or broken by the caller done with it: Resolution.release)
    with without_cyclic_gc("left"):
        return _resolve(line, selection)


def _resolve(line: ProductLine, selection: ProductSelection) -> Resolution:
    features, deselected, locations = selection.features, selection.deselected, selection.locations
    choices: list[CapabilityChoice] = []
    if selection.capabilities is not None:  # the robot's capabilities choose features too
        choices = choose_features(line.fm, selection.capabilities)
        features, deselected, locations = merge_choices(
            choices, features, deselected, locations, Location(selection.source, 1, 1)
        )
    completion = check_selection(  # step 1: an invalid or open selection is refused
        line.formula, features, deselected, locations, Location(selection.source, 1, 1)
    )
    completion.raise_unless_complete()
    selected = set(completion.features)
    sink = DiagnosticSink()
    attributes = product_attributes(line.fm, selected, selection, sink)
    sink.raise_if_errors()

    active = [  # the elements of the product, in file order
        element
        for element in line.rm.elements
        if (element.feature.name in selected) == element.activeIfSelected
    ]
    # step 2: what the product drops before anything reads it is not copied (pruning.py)
    left = pruning.left_out(line.unreferred_optionals, active)
    [system], copies = line.template_image.copy(left_out=left)
    trace = Trace()
    for feature in completion.added:
        trace.record(feature, "selected", "added by completion of the selection (feature model)")
    _apply_deployment(system, selection, sink)
    ctx = ResolutionContext(system, copies, trace, sink, attributes)
    ctx.left_out = _left_out_by_container(line.tsm, copies, left)

    for element in active:  # step 3, file order
        ctx.element = element
        for required in element.required:
            ctx.keep(
                ctx.copy_of(required), f"required by {describe(element)}", location_of(element)
            )
        for transformation in element.transformations:
            kind_of(transformation).apply(transformation, ctx)
    sink.raise_if_errors()  # step 3: conflicts found while applying

    _apply_sharing(ctx, active, selection)  # step 4
    sink.raise_if_errors()

    # pruning removes nodes: named as the template names them
    before = node_keys(system, ctx.left_out)
    pruning.prune_unkept(system, ctx.kept, trace, line.tsm, left)  # step 5
    implement_data_clients(system)
    warnings, cut = rewiring.rewire(system, trace, ctx.displaced)
    left_out = pruning.prune_unused(system, trace)

    flows = FlowTable.of(system)  # who talks to whom, for the checks and every output
    problems = check_architecture(system, flows, cut) + warnings  # step 7
    problems += shared_across_users(system) + unlinked_clouds(system)
    problems += cross_robot_flows(system, flows, trace)
    errors = [p for p in problems if p.severity == "error"]
    if errors:
        raise ModelError(errors)
    kept = tuple(n.name for c in system.containers for n in c.nodes)
    product = ResolvedProduct(
        name=selection.name,
        system=system,
        features=tuple(sorted(selected)),
        attributes=attributes,
        migrations=tuple(ctx.migrations),
        warnings=tuple(problems),
        left_out=left_out,
    )
    product.flows = flows
    system.name = line.tsm.name
    remaining = {id(n) for c in system.containers for n in c.nodes}
    removed = tuple(sorted(key for i, key in before.items() if i not in remaining))
    return Resolution(product, trace, completion, removed, kept, tuple(choices), copies)


def _left_out_by_container(
    template: tsm_types.System, copies: dict[int, EObject], left: set[int]
) -> dict[int, list[tsm_types.Node]]:
    """The template's nodes the copy left out, by the id of the container copying theirs."""
    found: dict[int, list[tsm_types.Node]] = {}
    for container in template.containers:
        nodes = [n for n in container.nodes if id(n) in left]
        if nodes:
            found[id(copies[id(container)])] = nodes
    return found


def product_attributes(
    fm: fm_types.FeatureModel, selected: set[str], selection: ProductSelection, sink: DiagnosticSink
) -> dict[str, AttributeValue]:
    """Attribute values of the product: defaults, overridden by the selection."""
    attributes: dict[str, tuple[AttributeValue, str]] = {}
    for feature in _features(fm.root):
        for attribute in feature.attributes:
            key = f"{feature.name}.{attribute.name}"
            attributes[key] = (_typed(attribute.value, attribute.type.name), attribute.type.name)
    values = {k: v for k, (v, _) in attributes.items()}
    for key, value in selection.attributes.items():
        where = selection.location(key)
        if key not in attributes:
            sink.error(where, f"unknown feature attribute {key}")
            continue
        kind = attributes[key][1]
        if isinstance(value, CommandLineValue):  # --set text, read by the declared type
            typed = typed_text(value, kind)
            if typed is None:
                sink.error(where, f"attribute {key} is {kind}, got {str(value)!r}")
                continue
            value = typed
        if not _fits(value, kind):
            sink.error(where, f"attribute {key} is {kind}, got {_shown(value)}")
            continue
        if key.split(".")[0] not in selected:
            sink.error(
                where, f"attribute {key} is set but feature {key.split('.')[0]} is not selected"
            )
            continue
        fitting = cast("AttributeValue", value)  # it fits its attribute's type
        values[key] = float(cast("float", fitting)) if kind == "double" else fitting
    return {k: v for k, v in sorted(values.items()) if k.split(".")[0] in selected}


def _shown(value: object) -> str:
    """A selection file's value as its YAML reads, not as Python writes it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return "nothing (null)"
    if isinstance(value, int | float | str):
        return repr(value) if isinstance(value, str) else str(value)
    return f"a {type(value).__name__} ({value})"


def _features(feature: fm_types.Feature) -> Iterator[fm_types.Feature]:
    yield feature
    for group in feature.groups:
        for child in group.features:
            yield from _features(child)


def _typed(text: str | None, kind: str) -> AttributeValue:
    if text is None:
        return None
    if kind == "int":
        return int(text)
    if kind == "double":
        return float(text)
    if kind == "bool":
        return text == "true"
    return text


def _fits(value: object, kind: str) -> bool:
    if isinstance(value, bool) or kind == "bool":
        return isinstance(value, bool) and kind == "bool"
    if kind == "int":
        return isinstance(value, int) and abs(value) <= literals.INT64_MAX
    if kind == "double":  # a NaN or infinite value cannot reach a launch file or JSON
        return isinstance(value, int | float) and math.isfinite(value)
    return isinstance(value, str) and not any(ord(c) < 32 for c in value)


def _apply_deployment(
    system: tsm_types.System, selection: ProductSelection, sink: DiagnosticSink
) -> None:
    robots = {c.name: c for c in system.containers if c.eClass.name == "RobotContainer"}
    for name, settings in sorted(selection.deployment.items()):
        container = robots.get(name)
        if container is None:
            sink.error(
                selection.location(f"deployment:{name}"), f"deployment: no robot container {name}"
            )
            continue
        if "robot_id" in settings:
            container.endpoint.robotId = settings["robot_id"]
        if "url" in settings:
            container.endpoint.url = settings["url"]


def _apply_sharing(
    ctx: ResolutionContext, active: list[rm_types.ResolutionElement], selection: ProductSelection
) -> None:
    """The sharing mode of a feature's functionality goes to the nodes its elements use."""
    T = tsm()
    features_with_sharing = set()
    for element in active:
        config = element.feature.sharing
        if config is None:
            continue
        feature = element.feature.name
        features_with_sharing.add(feature)
        mode = selection.sharing.get(feature, config.mode.name)
        origin = "product selection" if feature in selection.sharing else "feature model default"
        targets = [ctx.copy_of(target) for target in sharing_targets(element)]
        for node in targets:
            if not isinstance(node, T.Node):
                continue
            ctx.element = element
            if ctx.decide("sharing mode", node, mode, location_of(element)):
                # a mode of the feature model's or the selection's, both checked
                node.sharing = cast("tsm_types.SharingMode", T.SharingMode.getEEnumLiteral(mode))
                ctx.trace.record(
                    node.name,
                    "sharing",
                    f"{mode} ({origin} of feature {feature}), applied by {describe(element)}",
                    location_of(element),
                )
    for feature in sorted(selection.sharing):
        if feature not in features_with_sharing:
            ctx.sink.error(
                selection.location(f"sharing:{feature}"),
                f"sharing given for {feature}, which has no sharing attribute or no active "
                "resolution element in this product",
            )


def summary_lines(resolution: Resolution) -> list[str]:
    product = resolution.product
    lines = [f"product {product.name}: {', '.join(product.features)}"]
    for choice in resolution.capability_choices:
        lines.append(f"  {choice}")
    if resolution.completion.added:
        lines.append(f"  added by completion: {', '.join(resolution.completion.added)}")
    lines.append(
        f"  nodes kept: {len(resolution.kept_nodes)}, removed: {len(resolution.removed_nodes)}"
        + (f" ({', '.join(resolution.removed_nodes)})" if resolution.removed_nodes else "")
    )
    for migration in product.migrations:
        lines.append(f"  migrated: {migration.node} from {migration.source} to {migration.target}")
    for container, reason in product.left_out:
        lines.append(f"  left out: {container} ({reason})")
    return lines
