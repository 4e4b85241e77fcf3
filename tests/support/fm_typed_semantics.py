"""Brute-force semantics of UVL's Arithmetic and Type levels for tests: the products of a
SMALL typed model, the values of its typed features tried from a few candidates.

Independent of z3 on purpose (Python fractions and strings), with docs/fm.md's
semantics: a deselected typed feature, and an attribute of a deselected feature, are 0
(or ""); sum and avg leave deselected features out; a comparison that divides by zero
(avg of none included) is false; a Boolean feature as a number is 1 or 0. Exact where
every typed feature's domain is declared by constraints within the candidates.
"""

from __future__ import annotations

import math
from fractions import Fraction
from itertools import product as assignments
from typing import Any

from spl.dsl.fm.plain import to_ecore
from spl.dsl.interop.uvl_typed import TypedFeatureModel

from support.fm_semantics import products

# values brute force tries for a selected typed feature: a superset of every domain the
# generated models declare by constraints
CANDIDATES = {
    "Integer": [Fraction(v) for v in range(-1, 4)],
    "Real": [Fraction(v, 2) for v in range(-1, 5)],
    "String": ["", "a", "bc", "x"],
}
DEFAULT = {"Integer": Fraction(0), "Real": Fraction(0), "String": ""}


class _DividedByZero(Exception):
    pass


def _term(node: tuple, selected: frozenset[str], values: dict[str, object]) -> object:
    head = node[0]
    if head == "num":
        return Fraction(node[1])
    if head == "str":
        return node[1]
    if head == "value":
        return values[node[1]]
    if head == "selected":
        return Fraction(int(node[1] in selected))
    if head == "attr":
        _, feature, _, sort, value, _ = node
        if feature not in selected:
            return "" if sort == "str" else Fraction(0)
        return value if sort == "str" else Fraction(value)
    if head == "arith":
        left, right = _term(node[2], selected, values), _term(node[3], selected, values)
        assert isinstance(left, Fraction) and isinstance(right, Fraction)
        if node[1] == "/":
            if right == 0:
                raise _DividedByZero
            return left / right
        return {"+": left + right, "-": left - right, "*": left * right}[node[1]]
    if head == "len":
        return Fraction(len(str(_term(node[1], selected, values))))
    if head in ("floor", "ceil"):
        number = _term(node[1], selected, values)
        return Fraction((math.floor if head == "floor" else math.ceil)(number))  # type: ignore[call-overload]
    chosen = [v for f, v in node[1] if f in selected]
    total = sum((_term(v, selected, values) for v in chosen), Fraction(0))  # type: ignore[misc]
    if head == "sum":
        return total
    if not chosen:
        raise _DividedByZero
    return total / len(chosen)


def holds(node: tuple, selected: frozenset[str], values: dict[str, object]) -> bool:
    head = node[0]
    if head == "ref":
        return node[1] in selected
    if head == "not":
        return not holds(node[1], selected, values)
    if head == "cmp":
        try:
            left, right = _term(node[2], selected, values), _term(node[3], selected, values)
        except _DividedByZero:
            return False
        return {
            "==": left == right,
            "!=": left != right,
            "<": left < right,  # type: ignore[operator]
            "<=": left <= right,  # type: ignore[operator]
            ">": left > right,  # type: ignore[operator]
            ">=": left >= right,  # type: ignore[operator]
        }[node[1]]
    left, right = holds(node[1], selected, values), holds(node[2], selected, values)
    return {
        "and": left and right,
        "or": left or right,
        "implies": not left or right,
        "iff": left == right,
    }[head]


def brute_force(model: TypedFeatureModel) -> set[frozenset[str]]:
    """The products (sets of selected features) some values of the typed features make
    valid."""
    found = set()
    typed = sorted(model.types.items())
    for selected in products(to_ecore(model)):
        choices = [
            CANDIDATES[kind] if name in selected else [DEFAULT[kind]] for name, kind in typed
        ]
        for chosen in assignments(*choices):
            values = {name: value for (name, _), value in zip(typed, chosen, strict=True)}
            if all(holds(e.formula, selected, values) for e in model.equations):
                found.add(selected)
                break
    return found


def expected_analysis(model: TypedFeatureModel, formula: Any) -> dict[str, object]:
    valid = brute_force(model)
    names = set(formula.cnf.names)
    core = frozenset.intersection(*valid) if valid else frozenset()
    dead = names - frozenset().union(*valid) if valid else names
    cnf = formula.cnf
    false_optional = set()
    for name in names:
        parent = cnf.parent.get(name)
        if not valid or parent is None or name in cnf.modelled_mandatory or parent in dead:
            continue
        if all(name in p for p in valid if parent in p):
            false_optional.add(name)
    return {
        "satisfiable": bool(valid),
        "core": sorted(core),
        "dead": sorted(dead),
        "false_optional": sorted(false_optional),
        "count": len(valid),
    }


def analysis(formula: Any) -> dict[str, object]:
    return {
        "satisfiable": formula.satisfiable(),
        "core": formula.core_features(),
        "dead": formula.dead_features(),
        "false_optional": formula.false_optional_features(),
        "count": formula.count(None).value,
    }
