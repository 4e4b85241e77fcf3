"""The line ``spl check FILE.uvl`` prints for a model of the Arithmetic or Type level.

A Boolean model's summary counts features and constraints (``7 features, 4
constraints``). A typed model holds more than that, and a user checking one wants to
see that spl read all of it (docs/fm.md, "Typed features, cardinalities and
arithmetic"): its typed features by sort, its feature cardinalities, and its
constraints by kind, each equation under the first of these kinds it uses:

* ``aggregate``: ``sum`` or ``avg``;
* ``string``: a string literal, a String feature or attribute, or ``len``;
* ``arithmetic``: ``+ - * /``, ``floor`` or ``ceil``;
* ``comparison``: numbers compared, nothing more.

``bike.uvl``: ``11 features (1 Integer, 1 String), 1 feature cardinality, 6 constraints
(1 Boolean, 2 aggregate, 1 string, 2 comparison)``.
"""

from __future__ import annotations

from collections import Counter

from spl.core.diagnostics import counted
from spl.dsl.fm.plain import FeatureModel
from spl.dsl.interop.uvl_typed import TypedFeatureModel, features_of

KINDS = ("aggregate", "string", "arithmetic", "comparison")
SORTS = ("Integer", "Real", "String")


def summary(model: FeatureModel) -> str:
    """The model's one line: the Boolean counts, and for a typed model what it adds."""
    features = counted(len(features_of(model)), "feature")
    if not isinstance(model, TypedFeatureModel):
        return f"{features}, {counted(len(model.constraints), 'constraint')}"
    sorts = Counter(model.types.values())
    if sorts:
        features += " (" + ", ".join(f"{sorts[s]} {s}" for s in SORTS if sorts[s]) + ")"
    parts = [features]
    if model.cardinalities:
        many = len(model.cardinalities)
        parts.append(f"{many} feature cardinalit{'y' if many == 1 else 'ies'}")
    kinds = Counter(equation_kind(model, e.formula) for e in model.equations)
    total = len(model.constraints) + len(model.equations)
    shown = [f"{len(model.constraints)} Boolean"] + [f"{kinds[k]} {k}" for k in KINDS if kinds[k]]
    parts.append(counted(total, "constraint") + (f" ({', '.join(shown)})" if total else ""))
    return ", ".join(parts)


def equation_kind(model: TypedFeatureModel, formula: tuple) -> str:
    """The first of :data:`KINDS` the equation uses (an explicit stack: any depth)."""
    found: set[str] = set()
    work = [formula]
    while work:
        node = work.pop()
        head = node[0]
        if head in ("sum", "avg"):
            found.add("aggregate")
            work.extend(value for _, value in node[1])
            continue
        if (
            head in ("str", "len")
            or (head == "attr" and node[3] == "str")
            or (head == "value" and model.types.get(node[1]) == "String")
        ):
            found.add("string")
        elif head in ("arith", "floor", "ceil"):
            found.add("arithmetic")
        work.extend(part for part in node[1:] if isinstance(part, tuple))
    return next((kind for kind in KINDS if kind in found), "comparison")
