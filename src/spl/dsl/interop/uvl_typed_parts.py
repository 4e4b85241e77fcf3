"""Where a typed UVL model's first part that only the Arithmetic and Type levels hold
stands, in file order, an imported model's parts where its placement stands: what every
command that carries the Boolean level only refuses, located (docs/fm.md, "Conversion:
what each target keeps")."""

from __future__ import annotations

import sys

from spl.core.diagnostics import Location
from spl.dsl.fm.plain import Feature, Source
from spl.dsl.interop.interchange import written_names
from spl.dsl.interop.uvl_typed import TypedFeatureModel
from spl.dsl.interop.uvl_typed_writer import Aggregates, Unwritable, equation_text, uvl_id

# an equation named in a refusal is cut to this many characters
_SHOWN = 60


def dotted_name(name: str) -> str:
    """A dotted name (``sub.Feature``) as UVL writes each of its parts."""
    return ".".join(uvl_id(part) for part in name.split("."))


def first_typed_part(model: TypedFeatureModel) -> tuple[Location, str]:
    """Where the first part only the Arithmetic and Type levels hold is, and what it is."""
    written = written_names(model)
    names = {name: dotted_name(text) for name, text in written.items()}
    prefixes: dict[int, tuple[tuple[int, int], ...]] = {id(model.source): ()}
    previous: dict[int, Feature] = {}
    parts: list[tuple[tuple[tuple[int, int], ...], Source, int, str]] = []
    stack: list[tuple[Feature, Feature | None]] = [(model.root, None)] if model.root else []
    while stack:
        feature, parent = stack.pop()
        here = id(feature.source)
        if here not in prefixes:  # an imported root: its parts stand where it is placed
            outer = parent.source if parent is not None else model.source
            last = previous.get(id(outer))
            prefixes[here] = (*prefixes[id(outer)], (_next_line(outer, last), 1))
        previous[here] = feature
        prefix = prefixes[here]
        if feature.name in model.types:
            kind = model.types[feature.name]
            what = f"typed feature {written[feature.name]} ({kind})"
            parts.append(((*prefix, (feature.position, 0)), feature.source, feature.position, what))
        if feature.name in model.cardinalities:
            at = model.cardinalities[feature.name][2]
            what = f"feature cardinality of {written[feature.name]}"
            parts.append(((*prefix, (at, 0)), feature.source, at, what))
        children = [child for group in feature.groups for child in group.features]
        stack.extend((child, feature) for child in reversed(children))
    aggregates = Aggregates(model)
    for equation in model.equations:
        try:
            text = equation_text(equation.formula, names, aggregates)[0]
        except Unwritable:
            text = "with an aggregate"
        if len(text) > _SHOWN:
            text = text[: _SHOWN - 3] + "..."
        prefix = prefixes.get(id(equation.source), ())
        key = (*prefix, (equation.position, 0))
        parts.append((key, equation.source, equation.position, f"constraint {text}"))
    _, source, position, what = min(parts, key=lambda part: part[0])
    return source.location(position), what


def _next_line(source: Source, feature: Feature | None) -> int:
    """Where the line after ``feature``'s starts (0 before any feature)."""
    if feature is None:
        return 0
    line = source.location(feature.position).line
    starts = source.line_starts
    return starts[line] if line < len(starts) else sys.maxsize
