"""Brute-force feature-model semantics for tests: the set of products of a SMALL model.

Independent of the SAT analysis on purpose: it walks the tree (every configuration a
feature's groups allow once it is selected) and filters by the constraints, so the
importers and exporters can be checked to keep the product set, not only the shape.
"""

from __future__ import annotations

from itertools import combinations, product, product as assignments
from typing import Any

from spl.dsl.fm import language as fm


def products(model: Any) -> set[frozenset[str]]:
    """Every valid product of ``model`` as a set of selected feature names."""
    configurations = _selected(model.root)
    return {
        frozenset(names)
        for names in configurations
        if all(holds(c.formula, names) for c in model.constraints)
    }


def _selected(feature: Any) -> list[set[str]]:
    """The configurations of the subtree of ``feature`` given that it is selected."""
    per_group = [_group_options(group) for group in feature.groups]
    result = []
    for choice in product(*per_group):
        names = {feature.name}
        for part in choice:
            names |= part
        result.append(names)
    return result


def _group_options(group: Any) -> list[set[str]]:
    children = list(group.features)
    lower, upper = _bounds(group, len(children))
    options: list[set[str]] = []
    for size in range(lower, upper + 1):
        for chosen in combinations(children, size):
            for parts in product(*(_selected(child) for child in chosen)):
                merged: set[str] = set()
                for part in parts:
                    merged |= part
                options.append(merged)
    return options


def _bounds(group: Any, n: int) -> tuple[int, int]:
    """How many of a group's ``n`` members a selected parent takes (lower, upper)."""
    kind = group.kind.name
    if kind == "mandatory":
        return n, n
    if kind == "optional":
        return 0, n
    if kind == "alternative":
        return 1, 1
    if kind == "or":
        return 1, n
    upper = n if group.upper is None or group.upper == -1 else min(group.upper, n)
    return group.lower or 0, upper


def is_product(model: Any, selected: frozenset[str] | set[str]) -> bool:
    """Whether ``selected`` is a valid configuration of ``model`` (tree walk + formulas),
    for models too big to enumerate."""
    root = model.root
    if root.name not in selected:
        return False
    stack = [root]
    while stack:
        feature = stack.pop()
        on = feature.name in selected
        for group in feature.groups:
            children = list(group.features)
            chosen = sum(1 for child in children if child.name in selected)
            if not on and chosen:
                return False  # a child without its parent
            lower, upper = _bounds(group, len(children))
            if on and not lower <= chosen <= upper:
                return False
            stack.extend(children)
    return all(holds(c.formula, selected) for c in model.constraints)


def holds(formula: Any, names: frozenset[str] | set[str]) -> bool:
    """The truth of a constraint formula when exactly ``names`` are selected."""
    kind = formula.eClass.name
    if kind == "FeatureRef":
        return formula.feature.name in names
    if kind == "Not":
        return not holds(formula.operand, names)
    left, right = holds(formula.left, names), holds(formula.right, names)
    return {
        "and": left and right,
        "or": left or right,
        "implies": (not left) or right,
        "requires": (not left) or right,
        "iff": left == right,
        "excludes": not (left and right),
    }[formula.operator]


def relations(model) -> dict[str, tuple]:
    """Per feature: parent, relation to it, its group's members (for xor/or), abstract."""
    result = {}
    for feature in fm.all_features(model):
        parent = fm.parent_of(feature)
        group = feature.eContainer() if parent is not None else None
        kind = group.kind.name if group is not None else None
        if kind == "cardinality":
            kind = f"[{group.lower}..{group.upper}]"
        members = (
            frozenset(c.name for c in group.features)
            if group is not None and group.kind.name not in ("mandatory", "optional")
            else None
        )
        result[feature.name] = (parent.name if parent else None, kind, members, feature.abstract)
    return result


def _names(formula) -> set[str]:
    if formula.eClass.name == "FeatureRef":
        return {formula.feature.name}
    if formula.eClass.name == "Not":
        return _names(formula.operand)
    return _names(formula.left) | _names(formula.right)


def _shape(formula) -> tuple:
    """The formula as a tuple, with requires/excludes spelled as exporters spell them."""
    kind = formula.eClass.name
    if kind == "FeatureRef":
        return ("ref", formula.feature.name)
    if kind == "Not":
        return ("not", _shape(formula.operand))
    left, right = _shape(formula.left), _shape(formula.right)
    if formula.operator == "requires":
        return ("implies", left, right)
    if formula.operator == "excludes":
        return ("implies", left, ("not", right))
    return (formula.operator, left, right)


def equivalent(a, b) -> bool:
    """Equivalence of two constraint formulas: same shape, or else by truth table."""
    if _shape(a) == _shape(b):
        return True
    names = sorted(_names(a) | _names(b))
    for values in assignments((False, True), repeat=len(names)):
        true = {n for n, v in zip(names, values, strict=True) if v}
        if holds(a, true) != holds(b, true):
            return False
    return True
