"""Constraints of a UVL file: the grammar's ``constraint`` rule, read by operator precedence.

A mixin of :class:`spl.dsl.interop.uvl_reader.UvlReader` (which owns the tokens, the position
and the diagnostics): ``! > & > | > => > <=>``, binary operators left-associative, as
the reference grammar's alternatives order them; a constraint ends at its line break
(inside parentheses line breaks are not tokens). A formula is a tuple tree
(:mod:`spl.dsl.fm.plain`) naming features by their identifiers. The reader keeps its
own stacks instead of recursing, so no nesting or chain length runs out of Python's
stack; a constraint too deep for the rest of the toolchain is rebuilt with its ``&``
and ``|`` chains balanced before it is refused (docs/fm.md, "Limits").
"""

from __future__ import annotations

from collections.abc import Callable
from typing import ClassVar, NoReturn

from spl.dsl.fm.plain import Constraint, Source
from spl.dsl.fm.vocabulary import balanced_chains, formula_too_deep
from spl.dsl.interop.uvl_typed import Equation

# Tokens only an equation (arithmetic or attribute constraint) holds: a constraint with
# one is read by :mod:`spl.dsl.interop.uvl_equations`.
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


# "!" binds tighter than every binary operator (their precedences are 0 to 3).
_NOT = 4


class Syntax(Exception):
    """A syntax error already reported: the reader stops (a constraint line: that line)."""


class FormulaReader:
    """The constraint rules; the reader class provides the state named below."""

    tokens: list[tuple[str, str, int]]
    index: int
    identifiers: dict[str, str]
    unread: set[str]
    failed_names: bool
    source: Source
    error: Callable[[int, str], None]
    fail: Callable[[str], NoReturn]
    expect: Callable[[str, str], tuple[str, str, int]]
    equations: list[Equation]
    equation: Callable[[int], tuple]

    _BINARY: ClassVar[dict[str, tuple[str, int]]] = {
        "<=>": ("iff", 0),
        "=>": ("implies", 1),
        "|": ("or", 2),
        "&": ("and", 3),
    }

    # -- constraints -----------------------------------------------------------------
    def constraint_line(self) -> Constraint | None:
        tokens = self.tokens
        end = self.index
        while tokens[end][0] not in ("NL", "EOF"):
            end += 1
        constraint = self.constraint_between(end)
        self.index = end + 1 if tokens[end][0] == "NL" else end
        return constraint

    def constraint_between(self, end: int) -> Constraint | None:
        """The constraint from the current token to ``end``: a Boolean one returned, an
        equation (Arithmetic or Type level) kept with the reader's ``equations``."""
        tokens = self.tokens
        position = tokens[self.index][2]
        try:
            if any(kind in _ARITHMETIC for kind, _, _ in tokens[self.index : end]):
                self.equations.append(Equation(self.source, position, self.equation(end)))
                return None
            formula = self.formula()
            if self.index != end:
                self.fail("expected an operator (! & | => <=>)")
        except Syntax:
            formula = None
        refused = formula_too_deep(formula) if formula is not None else None
        if refused and formula is not None:  # built left-deep; its chains balanced may fit
            formula = balanced_chains(formula)
            refused = formula_too_deep(formula)
        if refused:
            self.error(position, refused)
            formula = None
        if formula is None or self.failed_names:
            self.failed_names = False
            return None
        return Constraint(self.source, position, formula)

    def formula(self) -> tuple:
        """Operator precedence with explicit stacks (no recursion: any nesting reads):
        ! > & > | > => > <=>, binary operators left-associative."""
        tokens = self.tokens
        binary = self._BINARY
        operands: list[tuple] = []
        # pending operators: (kind, precedence, position); "(" has none, "!" binds most
        pending: list[tuple[str, int, int]] = []

        def reduce(precedence: int) -> None:
            """Apply pending operators binding at least this tightly (to the last "(")."""
            while pending and pending[-1][0] != "(" and pending[-1][1] >= precedence:
                kind, _, position = pending.pop()
                if kind == "not":
                    operands.append(("not", operands.pop(), position))
                else:
                    right = operands.pop()
                    operands.append((kind, operands.pop(), right, position))

        while True:
            kind, _, position = tokens[self.index]
            while kind == "!" or kind == "(":  # prefixes of an operand
                pending.append(("not", _NOT, position) if kind == "!" else ("(", -1, position))
                self.index += 1
                kind, _, position = tokens[self.index]
            operands.append(self.reference_to_feature())
            while True:
                kind = tokens[self.index][0]
                entry = binary.get(kind)
                if entry is not None:
                    reduce(entry[1])
                    pending.append((entry[0], entry[1], tokens[self.index][2]))
                    self.index += 1
                    break
                reduce(0)
                if not pending:
                    return operands[0]
                self.expect(")", "')'")  # what is left open is a parenthesis
                pending.pop()

    def reference_to_feature(self) -> tuple:
        tokens = self.tokens
        index = self.index
        kind, text, position = tokens[index]
        if kind == "id" or kind == "qid":
            name = text[1:-1] if kind == "qid" else text
            index += 1
            while tokens[index][0] == "." and tokens[index + 1][0] in ("id", "qid"):
                part = tokens[index + 1][1]  # alias.Feature: an imported feature
                name += "." + (part[1:-1] if tokens[index + 1][0] == "qid" else part)
                index += 2
            self.index = index
            identifier = self.identifiers.get(name)
            if identifier is None and any(name.startswith(f"{a}.") for a in self.unread):
                self.failed_names = True  # a feature of an import refused at the import
                identifier = name
            elif identifier is None:
                self.error(position, f"unknown feature {name}")
                self.failed_names = True
                identifier = name
            return ("ref", identifier, position)
        self.fail("expected a feature, ! or (")
