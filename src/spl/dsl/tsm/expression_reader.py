"""Reading the transform expressions of ``tsm.tx`` (its rules ``Expression`` to ``Primary``).

Operators bind as the grammar's rules nest them: ``or``, ``and``, ``not``, comparisons,
``+ -``, ``* / %``, unary minus, indexing; each rule's object is built even when it
holds one operand, as textX does. Nesting is bounded (``MAX_DEPTH``): deeper
expressions are left to textX, whose own recursion refuses them at a depth of about 28
parentheses with the error the builder reports.
"""

from __future__ import annotations

from typing import Any

from spl.dsl.tsm.tree import (
    BOOLEAN,
    IDENT,
    QUOTED_STRING,
    UNSIGNED_NUMBER,
    Additive,
    AndExpr,
    BooleanLiteral,
    Call,
    Comparison,
    Index,
    Multiplicative,
    Negation,
    NotOp,
    NumberLiteral,
    OrExpr,
    Parenthesized,
    Postfix,
    Reference,
    Refused,
    StringLiteral,
    TsmTokens,
)

# Nesting (parentheses, calls, indexes, not, unary minus) read here; deeper is textX's.
MAX_DEPTH = 12
_COMPARISONS = ("<=", ">=", "==", "!=", "<", ">")


class ExpressionReader(TsmTokens):
    """The expression rules of the .tsm reader."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.depth = 0

    def expression(self) -> Any:
        self.deeper()
        operands = [self.and_expression()]
        while self.word()[1] == "or":
            self.keyword("or")
            operands.append(self.and_expression())
        self.depth -= 1
        return OrExpr(operands[0].position, operands)

    def deeper(self) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise Refused

    def nested(self, rule: Any) -> Any:
        """``rule()`` read one level deeper (the operand of ``not`` or unary minus)."""
        self.deeper()
        found = rule()
        self.depth -= 1
        return found

    def and_expression(self) -> Any:
        operands = [self.not_expression()]
        while self.word()[1] == "and":
            self.keyword("and")
            operands.append(self.not_expression())
        return AndExpr(operands[0].position, operands)

    def not_expression(self) -> Any:
        at, word = self.word()
        if word != "not":
            return self.comparison()
        self.pos = at + len(word)
        return NotOp(at, self.nested(self.not_expression))

    def comparison(self) -> Any:
        left = self.additive()
        at = self.skip()
        for operator in _COMPARISONS:
            if self.text.startswith(operator, at):
                self.pos = at + len(operator)
                return Comparison(left.position, left, operator, self.additive())
        return Comparison(left.position, left, None, None)

    def additive(self) -> Any:
        return self.chain(Additive, self.multiplicative, "+-")

    def multiplicative(self) -> Any:
        return self.chain(Multiplicative, self.unary, "*/%")

    def chain(self, rule: Any, operand: Any, operators: str) -> Any:
        """``operands=OPERAND (operators=OPERATOR operands=OPERAND)*``"""
        operands: list[Any] = [operand()]
        found: list[Any] = []
        while True:
            at = self.skip()
            symbol = self.text[at : at + 1]
            if not symbol or symbol not in operators:
                return rule(operands[0].position, operands, found)
            self.pos = at + 1
            found.append(symbol)
            operands.append(operand())

    def unary(self) -> Any:
        if not self.at("-"):
            return self.postfix()
        at = self.punct("-")
        return Negation(at, self.nested(self.unary))

    def postfix(self) -> Any:
        primary = self.primary()
        indexes = []
        while self.at("["):
            at = self.punct("[")
            indexes.append(Index(at, self.expression()))
            self.punct("]")
        return Postfix(primary.position, primary, indexes)

    def primary(self) -> Any:
        at = self.skip()
        text = self.text
        if UNSIGNED_NUMBER.match(text, at):
            return NumberLiteral(*self.match(UNSIGNED_NUMBER))
        if BOOLEAN.match(text, at):
            return BooleanLiteral(*self.match(BOOLEAN))
        if QUOTED_STRING.match(text, at):
            return StringLiteral(at, self.string())
        if IDENT.match(text, at):
            name = self.name()
            if not self.at("("):
                parts = [name]
                while self.at("."):
                    self.punct(".")
                    parts.append(self.name())
                return Reference(at, parts)
            self.punct("(")
            arguments = []
            if not self.at(")"):
                arguments.append(self.expression())
                while self.at(","):
                    self.punct(",")
                    arguments.append(self.expression())
            self.punct(")")
            return Call(at, name, arguments)
        self.punct("(")
        inner = self.expression()
        self.punct(")")
        return Parenthesized(at, inner)
