"""Constraints of the Arithmetic and Type levels: the grammar's ``equation`` and
``expression`` rules, with aggregate functions, inside Boolean constraints.

A mixin of :class:`spl.dsl.interop.uvl_reader.UvlReader`. A constraint holding any token
only an equation holds is read here (a Boolean one stays with
:mod:`spl.dsl.interop.uvl_formulas`, unchanged): one operator-precedence pass with
explicit stacks (``<=> < => < | < & < ! < comparisons < + - < * /``, binary operators
left-associative, as arithmetic is written), then each name is resolved by where it
stands: a feature where a Boolean is expected, a typed feature's value or an attribute
(``Feature.attribute``) where a number or string is (docs/fm.md, "Typed features,
cardinalities and arithmetic"). The tree is :mod:`spl.dsl.interop.uvl_typed`'s.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import ClassVar, NoReturn

from spl.dsl.fm.plain import Feature
from spl.dsl.interop.uvl_formulas import Syntax
from spl.dsl.interop.uvl_typed import NUMERIC_ATTRIBUTES, SORTS

_NAMES = ("id", "qid")
_BOOLEAN = {"<=>": "iff", "=>": "implies", "|": "or", "&": "and"}
_NOT = 4
_SHOWN = {"bool": "a condition", "num": "a number", "str": "a string"}
# the operands of each inner node of a raw equation: (index, the sort wanted there)
_PARTS: dict[str, tuple[tuple[int, str], ...]] = {
    "and": ((1, "bool"), (2, "bool")),
    "or": ((1, "bool"), (2, "bool")),
    "implies": ((1, "bool"), (2, "bool")),
    "iff": ((1, "bool"), (2, "bool")),
    "not": ((1, "bool"),),
    "cmp": ((2, "any"), (3, "any")),
    "arith": ((2, "num"), (3, "num")),
}


def _part(kind: str, text: str) -> str:
    return text[1:-1] if kind == "qid" else text


class EquationReader:
    """The equation rules; the reader class provides the state named below."""

    tokens: list[tuple[str, str, int]]
    index: int
    identifiers: dict[str, str]
    types: dict[str, str]
    by_identifier: dict[str, Feature]
    unread: set[str]  # aliases of imports refused
    written_values: dict[tuple[str, str], tuple[str, str]]  # attributes kept as written
    error: Callable[[int, str], None]
    fail: Callable[[str], NoReturn]
    expect: Callable[[str, str], tuple[str, str, int]]

    _PRECEDENCE: ClassVar[dict[str, int]] = {
        "<=>": 0,
        "=>": 1,
        "|": 2,
        "&": 3,
        "==": 5,
        "!=": 5,
        "<": 5,
        "<=": 5,
        ">": 5,
        ">=": 5,
        "+": 6,
        "-": 6,
        "*": 7,
        "/": 7,
    }

    def equation(self, end: int) -> tuple:
        """The constraint from the current token to ``end``, resolved and checked."""
        raw = self.raw_equation()
        if self.index != end:
            self.fail("expected an operator (! & | => <=> == != < <= > >= + - * /)")
        return self.resolved(raw, "bool")[0]

    def raw_equation(self) -> tuple:
        tokens = self.tokens
        precedence = self._PRECEDENCE
        operands: list[tuple] = []
        pending: list[tuple[str, int, int]] = []

        def reduce(bound: int) -> None:
            while pending and pending[-1][0] != "(" and pending[-1][1] >= bound:
                kind, _, position = pending.pop()
                if kind == "!":
                    operands.append(("not", operands.pop(), position))
                    continue
                right = operands.pop()
                left = operands.pop()
                if kind in _BOOLEAN:
                    operands.append((_BOOLEAN[kind], left, right, position))
                else:
                    head = "arith" if kind in "+-*/" else "cmp"
                    operands.append((head, kind, left, right, position))

        while True:
            kind, _, position = tokens[self.index]
            while kind in ("!", "("):
                pending.append((kind, _NOT if kind == "!" else -1, position))
                self.index += 1
                kind, _, position = tokens[self.index]
            operands.append(self.operand())
            while True:
                kind = tokens[self.index][0]
                bound = precedence.get(kind)
                if bound is not None:
                    reduce(bound)
                    pending.append((kind, bound, tokens[self.index][2]))
                    self.index += 1
                    break
                reduce(0)
                if not pending:
                    return operands[0]
                self.expect(")", "')'")
                pending.pop()

    def operand(self) -> tuple:
        kind, text, position = self.tokens[self.index]
        if kind in ("int", "float"):
            self.index += 1
            return ("num", text, position)
        if kind == "string":
            self.index += 1
            return ("str", text[1:-1], position)
        if kind in _NAMES:
            return ("name", self.dotted(), position)
        if kind in ("sum", "avg", "len", "floor", "ceil"):
            self.index += 1
            self.expect("(", f"'(' after {kind}")
            arguments = [self.dotted()]
            if kind in ("sum", "avg") and self.tokens[self.index][0] == ",":
                self.index += 1
                arguments.append(self.dotted())
            self.expect(")", f"')' closing {kind}")
            return ("call", kind, arguments, position)
        self.fail("expected a feature, a number, a 'string', an aggregate function, ! or (")

    def dotted(self) -> str:
        tokens = self.tokens
        kind, text, _ = tokens[self.index]
        if kind not in _NAMES:
            self.fail("expected a name")
        name = _part(kind, text)
        self.index += 1
        while tokens[self.index][0] == "." and tokens[self.index + 1][0] in _NAMES:
            name += "." + _part(*tokens[self.index + 1][:2])
            self.index += 2
        return name

    # -- names by where they stand ----------------------------------------------------
    def resolved(self, root: tuple, wanted: str) -> tuple[tuple, str]:
        """The tree with its names resolved, and its sort (bool, num, str); a sort other
        than the one its place wants is refused, located. Explicit stacks, like the
        parse: a chain of thousands of operators needs no Python stack."""
        done: list[tuple[tuple, str]] = []
        work: list[tuple[tuple, str, bool]] = [(root, wanted, False)]
        while work:
            node, want, ready = work.pop()
            head = node[0]
            parts = _PARTS.get(head)
            if parts is None:  # a leaf
                result, sort = self.leaf(node, want)
            elif not ready:
                work.append((node, want, True))
                work.extend((node[i], w, False) for i, w in reversed(parts))
                continue
            else:
                operands = done[len(done) - len(parts) :]
                del done[len(done) - len(parts) :]
                result, sort = self.combined(node, operands)
            if sort != want and want != "any":
                self.error(node[-1], f"expected {_SHOWN[want]} here, got {_SHOWN[sort]}")
                raise Syntax
            done.append((result, sort))
        return done[0]

    def leaf(self, node: tuple, wanted: str) -> tuple[tuple, str]:
        head = node[0]
        if head == "num" or head == "str":
            return node, head
        if head == "name":
            return self.name(node[1], node[-1], wanted)
        return self.call(node[1], node[2], node[-1])

    def combined(self, node: tuple, operands: list[tuple[tuple, str]]) -> tuple[tuple, str]:
        """A node over its resolved operands (``_PARTS`` gave each the sort it wants)."""
        head, position = node[0], node[-1]
        if head == "not":
            return ("not", operands[0][0], position), "bool"
        if head == "arith":
            return ("arith", node[1], operands[0][0], operands[1][0], position), "num"
        if head != "cmp":
            return (head, operands[0][0], operands[1][0], position), "bool"
        op = node[1]
        (left, left_sort), (right, right_sort) = operands
        if left_sort != right_sort or left_sort == "bool":
            self.error(
                position,
                f"{op} compares two numbers or two strings, not {_SHOWN[left_sort]} and "
                f"{_SHOWN[right_sort]}",
            )
            raise Syntax
        if left_sort == "str" and op not in ("==", "!="):
            self.error(position, f"strings compare with == and != only, not {op}")
            raise Syntax
        return ("cmp", op, left, right, position), "bool"

    def name(self, name: str, position: int, wanted: str) -> tuple[tuple, str]:
        identifier = self.identifiers.get(name)
        if wanted == "bool":
            if identifier is None:
                if not any(name.startswith(f"{alias}.") for alias in self.unread):
                    self.error(position, f"unknown feature {name}")
                raise Syntax
            return ("ref", identifier, position), "bool"
        if identifier is not None:
            kind = self.types.get(identifier)
            if kind is None:  # a Boolean feature as a number: 1 selected, 0 not
                return ("selected", identifier, position), "num"
            return ("value", identifier, position), SORTS[kind]
        owner, _, attribute = name.rpartition(".")
        identifier = self.identifiers.get(owner)
        if not owner or identifier is None:
            if not any(name.startswith(f"{alias}.") for alias in self.unread):
                self.error(position, f"unknown feature or attribute {name}")
            raise Syntax  # a feature of an import refused at the import: said there
        found = self.attribute_value(identifier, attribute)
        if found is None:  # declared without a value: a variable (docs/fm.md)
            sort = "str" if wanted == "str" else "num"
            return ("attr", identifier, attribute, sort, None, position), sort
        if found[0] not in (*NUMERIC_ATTRIBUTES, "string"):
            self.error(position, f"attribute {name} is {found[0]}, not a number or string")
            raise Syntax
        sort = "str" if found[0] == "string" else "num"
        return ("attr", identifier, attribute, sort, found[1], position), sort

    def attribute_value(self, identifier: str, attribute: str) -> tuple[str, str] | None:
        """(type, value) of a feature's attribute, None when it has none of that name."""
        feature = self.by_identifier[identifier]
        for found in feature.attributes:
            if found.name == attribute:
                return found.type, found.value
        return self.written_values.get((identifier, attribute))

    def call(self, function: str, arguments: list[str], position: int) -> tuple[tuple, str]:
        """An aggregate function; ``sum`` and ``avg`` as (selection, value) terms."""
        if function in ("len", "floor", "ceil"):
            wanted = "str" if function == "len" else "num"
            operand = self.resolved(("name", arguments[0], position), wanted)[0]
            return (function, operand, position), "num"
        terms: list[tuple[str, tuple]] = []
        features = [a for a in arguments if a in self.identifiers]
        if len(features) == len(arguments) or (len(arguments) == 1 and "." in arguments[0]):
            for argument in arguments:  # the values of the features (or attribute) named
                value = self.resolved(("name", argument, position), "num")[0]
                owner = value[1]
                terms.append((owner, value))
            return (function, tuple(terms), position), "num"
        attribute = next(a for a in arguments if a not in features)
        if len(arguments) == 2 and not features:
            self.error(
                position,
                f"{function} takes an attribute name and, optionally, the feature whose "
                "subtree it aggregates",
            )
            raise Syntax
        scope = self.subtree(self.identifiers[features[0]]) if features else self.by_identifier
        for identifier in scope:
            found = self.attribute_value(identifier, attribute)
            if found is not None and found[0] in NUMERIC_ATTRIBUTES:
                attr = ("attr", identifier, attribute, "num", found[1], position)
                terms.append((identifier, attr))
        if not terms:
            self.error(position, f"no feature has a number attribute {attribute}")
            raise Syntax
        return (function, tuple(terms), position), "num"

    def subtree(self, identifier: str) -> list[str]:
        """The feature and its descendants, in pre-order."""
        found: list[str] = []
        work = [self.by_identifier[identifier]]
        while work:
            feature = work.pop()
            found.append(feature.name)
            for group in reversed(feature.groups):
                work.extend(reversed(group.features))
        return found
