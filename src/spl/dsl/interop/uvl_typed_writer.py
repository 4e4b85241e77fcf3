"""Writing the Arithmetic and Type levels of UVL back: equations, levels, typed parts.

``spl convert`` from UVL to UVL keeps a typed model whole (docs/fm.md, "Conversion:
what each target keeps"): the tree is written by :func:`spl.dsl.interop.uvl.write_uvl`,
and this module gives it what only a typed model has: each feature's type and
cardinality, the equations as text the UVL reader reads back to the same tree
(:mod:`spl.dsl.interop.uvl_equations`), and the ``include`` lines naming the levels the
file uses.

An equation is printed with explicit stacks, like it is read: a chain of thousands of
``+`` needs no Python stack. Aggregates come back as the reader expanded them:
``sum(attr)`` when the terms are every feature with that number attribute,
``sum(attr, F)`` for ``F``'s subtree, ``sum(F, G)`` for named values.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

from spl.core.diagnostics import Diagnostic, ModelError
from spl.dsl.fm.plain import Feature
from spl.dsl.interop.uvl_lexer import KEYWORDS
from spl.dsl.interop.uvl_typed import (
    NUMERIC_ATTRIBUTES,
    TypedFeatureModel,
    features_of,
    subtree_features,
)

_PLAIN = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
_KEYWORDS = KEYWORDS | {"abstract"}
# precedence as the reader binds (uvl_equations: loosest first), atoms above all
_LEVEL = {"iff": 0, "implies": 1, "or": 2, "and": 3, "not": 4, "cmp": 5}
_ARITH_LEVEL = {"+": 6, "-": 6, "*": 7, "/": 7}
_ATOM = 8
_BOOLEAN = {"iff": "<=>", "implies": "=>", "or": "|", "and": "&"}
_SLOTS = {"cmp": (2, 3), "arith": (2, 3), "not": (1,), "len": (1,), "floor": (1,), "ceil": (1,)}
# the language levels, in the order an include section lists them
LEVELS = (
    "Boolean",
    "Boolean.group-cardinality",
    "Arithmetic",
    "Arithmetic.feature-cardinality",
    "Arithmetic.aggregate-function",
    "Type",
    "Type.string-constraints",
)


def uvl_id(name: str) -> str:
    """One name part as UVL writes it: plain, or double-quoted (a caller has refused the
    characters a quoted name cannot hold)."""
    return name if _PLAIN.match(name) and name not in _KEYWORDS else f'"{name}"'


@dataclass
class UvlFile:
    """What one UVL file of a conversion holds beyond a Boolean model's tree and
    constraints (:func:`spl.dsl.interop.uvl.write_uvl` reads it by feature identifier):
    the file its own elements were read from (the others are an imported model's, which
    a file of its own writes), each feature's name as UVL text, the namespace, ``include``
    and ``imports`` lines, and the typed parts."""

    own: str
    names: dict[str, str]
    namespace: str = ""
    imports: list[str] = field(default_factory=list)
    types: dict[str, str] = field(default_factory=dict)
    cardinalities: dict[str, tuple[int, int]] = field(default_factory=dict)
    equations: list[str] = field(default_factory=list)
    levels: list[str] = field(default_factory=list)


def add_typed_parts(parts: UvlFile, model: TypedFeatureModel, owned: Callable[[str], bool]) -> None:
    """The equations of ``model`` the file writes (those read from it) and the levels
    the file uses, its types and cardinalities given (``owned``: whether the file
    declares a feature, by identifier)."""
    names = parts.names
    file = model.source.file
    used: set[str] = set()
    aggregates = Aggregates(model)
    if parts.types:
        used.add("Type")
    if parts.cardinalities:
        used.add("Arithmetic.feature-cardinality")
    problems = []
    for equation in model.equations:
        if equation.source.file != file:  # its own file writes it
            continue
        try:
            text, levels = equation_text(equation.formula, names, aggregates)
        except Unwritable as exc:
            where = equation.source.location(equation.position)
            problems.append(Diagnostic(where, f"{exc} cannot be written as UVL that reads back"))
            continue
        parts.equations.append(text)
        used |= levels
    if problems:
        raise ModelError(problems)
    if any(g.kind == "cardinality" for f in features_of(model) if owned(f.name) for g in f.groups):
        used.add("Boolean.group-cardinality")
    if used:
        used |= {"Boolean", *(level.partition(".")[0] for level in used)}
    parts.levels = [level for level in LEVELS if level in used]


class Aggregates:
    """The features an aggregate over an attribute can name, for writing one back."""

    def __init__(self, model: TypedFeatureModel) -> None:
        self.order = features_of(model)
        self.by_name = {feature.name: feature for feature in self.order}
        self.types = model.types
        self.parents = {
            child.name: feature
            for feature in self.order
            for group in feature.groups
            for child in group.features
        }

    def with_attribute(self, attribute: str, scope: list[Feature]) -> list[str]:
        """The features of ``scope`` whose ``attribute`` the reader aggregates."""
        return [
            feature.name
            for feature in scope
            if any(a.name == attribute and a.type in NUMERIC_ATTRIBUTES for a in feature.attributes)
        ]

    def scope_of(self, attribute: str, terms: list[str]) -> str | None:
        """The feature whose subtree's ``attribute`` gives exactly ``terms`` (the root
        first: ``sum(attr)``; then the deepest, the shortest to read back), None when no
        subtree does."""
        if self.with_attribute(attribute, self.order) == terms:
            return self.order[0].name
        feature: Feature | None = self.by_name.get(terms[0]) if terms else None
        while feature is not None:  # the scope holds the first term: one of its ancestors
            if self.with_attribute(attribute, subtree_features(feature)) == terms:
                return feature.name
            feature = self.parents.get(feature.name)
        return None


def equation_text(
    formula: tuple, names: dict[str, str], aggregates: Aggregates
) -> tuple[str, set[str]]:
    """An equation's tree as UVL text with the fewest parentheses the reader's
    precedence allows (nested implications and equivalences always parenthesised, as
    the Boolean writer does), and the language levels it uses."""
    levels = {"Arithmetic"}
    done: list[tuple[str, int]] = []
    work: list[tuple[tuple, bool]] = [(formula, False)]
    while work:
        node, ready = work.pop()
        head = node[0]
        slots = (1, 2) if head in _BOOLEAN else _SLOTS.get(head, ())
        if slots and not ready:
            work.append((node, True))
            work.extend((node[i], False) for i in reversed(slots))
            continue
        operands = done[len(done) - len(slots) :] if slots else []
        if slots:
            del done[len(done) - len(slots) :]
        done.append(_node_text(node, operands, names, aggregates, levels))
    return done[0][0], levels


def _node_text(
    node: tuple,
    operands: list[tuple[str, int]],
    names: dict[str, str],
    aggregates: Aggregates,
    levels: set[str],
) -> tuple[str, int]:
    head = node[0]
    if head in _BOOLEAN or head in ("cmp", "arith"):
        if head in _BOOLEAN:
            level, symbol = _LEVEL[head], _BOOLEAN[head]
        elif head == "cmp":
            level, symbol = _LEVEL["cmp"], node[1]
        else:
            level, symbol = _ARITH_LEVEL[node[1]], node[1]
        (left, left_level), (right, right_level) = operands
        if left_level < level or (level <= 1 and left_level <= level):
            left = f"({left})"
        if right_level <= level:
            right = f"({right})"
        return f"{left} {symbol} {right}", level
    if head == "not":
        inner, inner_level = operands[0]
        # a comparison under ! is parenthesised too, though ! binds looser: read at a glance
        wrapped = inner if inner_level in (_LEVEL["not"], _ATOM) else f"({inner})"
        return "!" + wrapped, _LEVEL["not"]
    if head in ("len", "floor", "ceil"):
        levels.add("Type.string-constraints" if head == "len" else "Arithmetic.aggregate-function")
        return f"{head}({operands[0][0]})", _ATOM
    if head == "ref" or head == "value" or head == "selected":
        return names[node[1]], _ATOM
    if head == "attr":
        if node[3] == "str":
            levels.add("Type.string-constraints")
        return f"{names[node[1]]}.{uvl_id(node[2])}", _ATOM
    if head == "num":
        return node[1], _ATOM
    if head == "str":
        levels.add("Type.string-constraints")
        return f"'{node[1]}'", _ATOM
    levels.add("Arithmetic.aggregate-function")
    return _aggregated(head, node[1], names, aggregates)


def _aggregated(
    function: str, terms: tuple, names: dict[str, str], aggregates: Aggregates
) -> tuple[str, int]:
    """``sum``/``avg`` as the reader expands it to ``terms``, and its precedence."""
    values = [value for _, value in terms]
    attributes = {value[2] for value in values if value[0] == "attr"}
    if not (len(attributes) == 1 and all(value[0] == "attr" for value in values)):
        return f"{function}({', '.join(names[value[1]] for value in values)})", _ATOM
    attribute = attributes.pop()
    owners = [value[1] for value in values]
    scope = aggregates.scope_of(attribute, owners)
    if scope == aggregates.order[0].name:
        return f"{function}({uvl_id(attribute)})", _ATOM
    if scope is not None:
        return f"{function}({uvl_id(attribute)}, {names[scope]})", _ATOM
    if len(values) == 1:  # one attribute, named as Feature.attribute
        return f"{function}({names[owners[0]]}.{uvl_id(attribute)})", _ATOM
    # No scope gives these terms (an attribute name kept as written, which spl holds as
    # text): the same value spelled out, an attribute of a deselected feature being 0
    # and avg's divisor the features selected (docs/fm.md).
    total = " + ".join(f"{names[owner]}.{uvl_id(attribute)}" for owner in owners)
    if function == "sum":
        return f"({total})", _ATOM
    if any(owner in aggregates.types for owner in owners):
        raise Unwritable(f"avg({uvl_id(attribute)}) over typed features")
    return f"({total}) / ({' + '.join(names[owner] for owner in owners)})", _ARITH_LEVEL["/"]


class Unwritable(Exception):
    """An equation part UVL text cannot say so that it reads back the same."""
