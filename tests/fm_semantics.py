"""Brute-force feature-model semantics for tests: the set of products of a SMALL model.

Independent of the SAT analysis on purpose: it walks the tree (every configuration a
feature's groups allow once it is selected) and filters by the constraints, so the
importers and exporters can be checked to keep the product set, not only the shape.
"""

from __future__ import annotations

from itertools import combinations, product
from typing import Any


def products(model: Any) -> set[frozenset[str]]:
    """Every valid product of ``model`` as a set of selected feature names."""
    configurations = _selected(model.root)
    return {
        frozenset(names)
        for names in configurations
        if all(_holds(c.formula, names) for c in model.constraints)
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
    kind = group.kind.name
    if kind == "mandatory":
        lower, upper = len(children), len(children)
    elif kind == "optional":
        lower, upper = 0, len(children)
    elif kind == "alternative":
        lower, upper = 1, 1
    elif kind == "or":
        lower, upper = 1, len(children)
    else:
        lower = group.lower
        upper = len(children) if group.upper == -1 else group.upper
    options: list[set[str]] = []
    for size in range(lower, min(upper, len(children)) + 1):
        for chosen in combinations(children, size):
            for parts in product(*(_selected(child) for child in chosen)):
                merged: set[str] = set()
                for part in parts:
                    merged |= part
                options.append(merged)
    return options


def _holds(formula: Any, names: set[str]) -> bool:
    kind = formula.eClass.name
    if kind == "FeatureRef":
        return formula.feature.name in names
    if kind == "Not":
        return not _holds(formula.operand, names)
    left, right = _holds(formula.left, names), _holds(formula.right, names)
    return {
        "and": left and right,
        "or": left or right,
        "implies": (not left) or right,
        "requires": (not left) or right,
        "iff": left == right,
        "excludes": not (left and right),
    }[formula.operator]
