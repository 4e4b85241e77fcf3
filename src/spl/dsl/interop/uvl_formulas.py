"""Constraints of a UVL file: the grammar's ``constraint`` rule, read by precedence climbing.

A mixin of :class:`spl.dsl.interop.uvl_reader.UvlReader` (which owns the tokens, the position
and the diagnostics): ``! > & > | > => > <=>``, binary operators left-associative, as
the reference grammar's alternatives order them; a constraint ends at its line break
(inside parentheses line breaks are not tokens). A formula is a tuple tree
(:mod:`spl.dsl.fm.plain`) naming features by their identifiers.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import ClassVar, NoReturn

from spl.dsl.fm.plain import Constraint, Source
from spl.dsl.fm.vocabulary import formula_too_deep

# Tokens only an equation (arithmetic or attribute constraint) holds.
_ARITHMETIC = frozenset(
    (
        "==",
        "<",
        ">",
        "<=",
        ">=",
        "!=",
        "+",
        "-",
        "*",
        "/",
        "int",
        "float",
        "string",
        "sum",
        "avg",
        "len",
        "floor",
        "ceil",
    )
)


class Syntax(Exception):
    """A syntax error already reported: the reader stops (a constraint line: that line)."""


class FormulaReader:
    """The constraint rules; the reader class provides the state named below."""

    tokens: list[tuple[str, str, int]]
    index: int
    identifiers: dict[str, str]
    failed_names: bool
    source: Source
    error: Callable[[int, str], None]
    fail: Callable[[str], NoReturn]
    expect: Callable[[str, str], tuple[str, str, int]]

    _BINARY: ClassVar[dict[str, tuple[str, int]]] = {
        "<=>": ("iff", 0),
        "=>": ("implies", 1),
        "|": ("or", 2),
        "&": ("and", 3),
    }

    # -- constraints -----------------------------------------------------------------
    def constraint_line(self) -> Constraint | None:
        tokens = self.tokens
        start = self.index
        end = start
        while tokens[end][0] not in ("NL", "EOF"):
            end += 1
        position = tokens[start][2]
        try:
            for kind, _, at in tokens[start:end]:
                if kind in _ARITHMETIC:
                    self.error(at, "arithmetic and attribute constraints are not supported")
                    raise Syntax
            formula = self.formula(0)
            if self.index != end:
                self.fail("expected an operator (! & | => <=>)")
        except Syntax:
            formula = None
        self.index = end + 1 if tokens[end][0] == "NL" else end
        refused = formula_too_deep(formula) if formula is not None else None
        if refused:
            self.error(position, refused)
            formula = None
        if formula is None or self.failed_names:
            self.failed_names = False
            return None
        return Constraint(self.source, position, formula)

    def formula(self, level: int) -> tuple:
        """Precedence climbing: ! > & > | > => > <=>, binary operators left-associative."""
        left = self.unary()
        tokens = self.tokens
        binary = self._BINARY
        while True:
            kind, _, position = tokens[self.index]
            entry = binary.get(kind)
            if entry is None or entry[1] < level:
                return left
            self.index += 1
            left = (entry[0], left, self.formula(entry[1] + 1), position)

    def unary(self) -> tuple:
        tokens = self.tokens
        index = self.index
        kind, text, position = tokens[index]
        if kind == "id" or kind == "qid":  # the most frequent case first, inline
            if tokens[index + 1][0] == ".":
                self.error(position, "a dotted reference (an imported feature) is not supported")
                raise Syntax
            self.index = index + 1
            name = text[1:-1] if kind == "qid" else text
            identifier = self.identifiers.get(name)
            if identifier is None:
                self.error(position, f"unknown feature {name}")
                self.failed_names = True
                identifier = name
            return ("ref", identifier, position)
        if kind == "!":
            self.index = index + 1
            return ("not", self.unary(), position)
        if kind == "(":
            self.index = index + 1
            inner = self.formula(0)
            self.expect(")", "')'")
            return inner
        self.fail("expected a feature, ! or (")
