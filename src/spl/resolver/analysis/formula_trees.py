"""Cross-tree constraint formulas as trees of plain tuples.

``("ref", name) | ("not", tree) | (operator, left, right)``: one pass turns a pyecore
formula into this shape, and from then on the CNF encoding (:mod:`spl.resolver.analysis.cnf`) and
selection checking (:mod:`spl.resolver.resolution.selection`) read tuples, which is several times
faster than attribute access through pyecore. A plain model's trees
(:mod:`spl.dsl.fm.plain`) have this shape plus a trailing source position per node,
which everything reading trees by index ignores.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

if TYPE_CHECKING:
    from spl.metamodels import fm_types


def formula_tree(formula: fm_types.Formula) -> tuple:
    """A constraint formula (pyecore) as plain tuples."""
    cls = type(formula).__name__
    if cls == "FeatureRef":
        return ("ref", cast("fm_types.FeatureRef", formula).feature.name)
    if cls == "Not":
        return ("not", formula_tree(cast("fm_types.Not", formula).operand))
    binary = cast("fm_types.BinaryFormula", formula)
    return (binary.operator, formula_tree(binary.left), formula_tree(binary.right))


def formula_features(tree: tuple) -> tuple[str, ...]:
    """The features a formula tree mentions, in first-use order (one pass: the long
    or-chains of kernel models made the recursive concatenation quadratic)."""
    found: dict[str, None] = {}
    stack = [tree]
    while stack:
        node = stack.pop()
        head = node[0]
        if head == "ref":
            found[node[1]] = None
        elif head == "not":
            stack.append(node[1])
        else:
            stack.append(node[2])
            stack.append(node[1])
    return tuple(found)


def evaluate(tree: tuple, product: set[str] | frozenset[str]) -> bool:
    """The truth of a formula tree in a product (a set of feature names)."""
    head = tree[0]
    if head == "ref":
        return tree[1] in product
    if head == "not":
        return not evaluate(tree[1], product)
    a, b = evaluate(tree[1], product), evaluate(tree[2], product)
    if head == "and":
        return a and b
    if head == "or":
        return a or b
    if head in ("implies", "requires"):
        return (not a) or b
    if head == "excludes":
        return not (a and b)
    if head == "iff":
        return a == b
    raise ValueError(f"unknown operator {head!r}")
