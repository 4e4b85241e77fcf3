"""The words and values every feature-model reader shares (.fm, UVL, FeatureIDE XML).

Kept apart from the .fm parser (``spl.dsl.fm.language``, which loads textX and the pyecore
metamodel) so the UVL reader and ``spl analyze`` can use them without paying for
either import.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any, TypeVar

from spl.core.diagnostics import Diagnostic, Location
from spl.dsl import grammar_keywords, literals

# Words of the .fm language that can never name a feature (the grammar's FeatureName
# refuses them); importers rename features called like this.
RESERVED_WORDS = grammar_keywords.excluded_words("fm", "FeatureName")
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
ATTRIBUTE_TYPES = grammar_keywords.words_of("fm", "AttributeType")  # int, double, ...
SHARING_MODES = grammar_keywords.words_of("fm", "SharingModeName")  # public, protected, ...
# Binary operators of the metamodel, as the .fm language spells them.
OPERATORS = ("and", "or", "implies", "iff", "requires", "excludes")


def is_feature_name(name: str) -> bool:
    """True when ``name`` can be written as a feature name in a .fm file."""
    return bool(IDENTIFIER.match(name)) and name not in RESERVED_WORDS


def too_deep(filename: str) -> Diagnostic:
    """The error for input nested beyond what the readers follow (a hostile file)."""
    return Diagnostic(
        Location(filename, 1, 1), "the model is nested too deeply (features or parentheses)"
    )


def canonical_value(type_name: str, text: str) -> str | None:
    """The canonical text of a default value of ``type_name``, or None when it does not fit.

    Canonical means one spelling per value (``1.0`` and ``1.`` are the same double), so
    comparing models compares values, and every importer agrees with the .fm language.
    """
    if type_name == "bool":
        return text if text in ("true", "false") else None
    if type_name == "int":
        value = literals.int_literal(text)
        return str(value) if value is not None else None
    if type_name == "double":
        try:
            number = float(text)
        except ValueError:
            return None
        if number != number or number in (float("inf"), float("-inf")):
            return None
        return repr(number)
    return text


# Operators on the longest path of one constraint from its root to a feature. Every
# reader refuses deeper constraints: the encodings, printers and checks walk formulas
# recursively and would each run out of Python's stack. A chain of one `and` or `or`
# operator is no limit: the readers make binary operators left-associative, and a
# constraint that would be too deep so is built with each such chain (across
# parentheses too) as a balanced tree instead, 14 levels for 10,000 operands
# (docs/fm.md, "Limits"). The deepest constraint of the community corpus (the Linux
# kernel models) is 28 levels. A FeatureIDE export nests one element per level below
# <featureModel><constraints><rule>, and lxml reads no XML deeper than 256 elements.
MAX_FORMULA_DEPTH = 200

Joined = TypeVar("Joined")


def balanced(operands: list[Joined], join: Callable[[Joined, Joined], Joined]) -> Joined:
    """``operands`` joined by an associative operator as a balanced tree (depth
    ceil(log2 n)), in their order: ``join(join(a, b), join(c, d))``. No recursion."""
    level = operands
    while len(level) > 1:
        paired = [join(level[i], level[i + 1]) for i in range(0, len(level) - 1, 2)]
        if len(level) % 2:
            paired.append(level[-1])
        level = paired
    return level[0]


def balanced_chains(tree: tuple) -> tuple:
    """A tuple formula tree (:mod:`spl.dsl.fm.plain`) meaning the same, each maximal chain
    of one ``and`` or ``or`` operator rebuilt as a :func:`balanced` tree (the new nodes
    are located where the chain's top operator was). No recursion: any depth is."""
    done: list[tuple] = []
    work: list[tuple[tuple, int]] = [(tree, -1)]  # (node, -1: to visit | operands to join)
    while work:
        node, count = work.pop()
        head = node[0]
        if count >= 0:  # the operands are built: the last ``count`` of ``done``
            parts = done[len(done) - count :]
            del done[len(done) - count :]
            if head in ("and", "or"):
                done.append(balanced(parts, _joining(node)))
            elif head == "not":
                done.append((head, parts[0], *node[2:]))
            else:
                done.append((head, parts[0], parts[1], *node[3:]))
        elif head == "ref":
            done.append(node)
        elif head == "not":
            work.extend([(node, 1), (node[1], -1)])
        else:
            operands = [node[1], node[2]]
            if head in ("and", "or"):  # the whole chain, in order, as one node's operands
                operands, stack = [], [node]
                while stack:
                    part = stack.pop()
                    if part[0] == head:
                        stack.extend((part[2], part[1]))
                    else:
                        operands.append(part)
            work.append((node, len(operands)))
            work.extend((operand, -1) for operand in reversed(operands))
    return done[0]


def formula_too_deep(formula: Any) -> str | None:
    """Why a constraint's formula (pyecore, or a tuple tree of ``spl.dsl.fm.plain``) is
    refused for its depth, or None. Measured without recursion, so any depth is."""
    deepest, stack = 0, [(formula, 0)]
    while stack:
        node, depth = stack.pop()
        deepest = max(deepest, depth)
        if isinstance(node, tuple):
            head = node[0]
            children = () if head == "ref" else (node[1],) if head == "not" else node[1:3]
        else:
            kind = type(node).__name__
            children = (
                ()
                if kind == "FeatureRef"
                else (node.operand,)
                if kind == "Not"
                else (node.left, node.right)
            )
        stack.extend((child, depth + 1) for child in children if child is not None)
    if deepest <= MAX_FORMULA_DEPTH:
        return None
    return (
        f"constraint nested {deepest} operators deep (at most {MAX_FORMULA_DEPTH}, a chain of "
        "one 'and' or 'or' counting as a balanced tree): split it into several constraints"
    )


def _joining(chain: tuple) -> Callable[[tuple, tuple], tuple]:
    """Joins two operands with the operator (and location) of ``chain``'s top node."""
    return lambda left, right: (chain[0], left, right, *chain[3:])
