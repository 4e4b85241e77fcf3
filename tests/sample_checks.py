"""Independent checks of samples for the products/validate tests.

Nothing here uses the CNF encoding or the sampler: a product is checked against the
feature tree and the constraints directly, and the combinations a set of products
covers are counted from the feature names.
"""

from __future__ import annotations

from itertools import combinations
from typing import Any


def is_product(model: Any, selected: frozenset[str] | set[str]) -> bool:
    """Whether ``selected`` is a valid configuration of ``model`` (tree walk + formulas)."""
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


def _bounds(group: Any, n: int) -> tuple[int, int]:
    kind = group.kind.name
    if kind == "mandatory":
        return n, n
    if kind == "optional":
        return 0, n
    if kind == "alternative":
        return 1, 1
    if kind == "or":
        return 1, n
    upper = n if group.upper is None or group.upper == -1 else group.upper
    return group.lower or 0, upper


def holds(formula: Any, selected: frozenset[str] | set[str]) -> bool:
    kind = formula.eClass.name
    if kind == "FeatureRef":
        return formula.feature.name in selected
    if kind == "Not":
        return not holds(formula.operand, selected)
    a, b = holds(formula.left, selected), holds(formula.right, selected)
    op = formula.operator
    if op == "and":
        return a and b
    if op == "or":
        return a or b
    if op in ("implies", "requires"):
        return (not a) or b
    if op == "excludes":
        return not (a and b)
    if op == "iff":
        return a == b
    raise ValueError(op)


def interactions(products: Any, names: list[str], t: int) -> set[tuple[tuple[str, bool], ...]]:
    """Every t-combination of feature literals (name, selected) some product contains."""
    found: set[tuple[tuple[str, bool], ...]] = set()
    for product in products:
        literals = [(name, name in product) for name in names]
        found.update(combinations(literals, t))
    return found
