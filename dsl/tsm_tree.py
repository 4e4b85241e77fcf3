"""The parse tree of ``tsm.tx`` as textX shapes it, and the terminals it is read from.

One class per grammar rule, named after it, holding the rule's attributes (``None``,
``False`` or ``[]`` where textX leaves them unset) and ``_tx_position``, the offset of
its first token: the builder (``spl.dsl.tsm``) reads these exactly as it reads textX's
objects. :class:`Tokens` matches the terminals the way textX does: blanks and comments
are skipped before every terminal, keywords must end at a word boundary (textX's
autokwd), regular expressions are the grammar's own.
"""

from __future__ import annotations

import re
from collections import namedtuple
from operator import itemgetter
from typing import Any

# The regular expressions of tsm.tx, as textX compiles them (re.MULTILINE is arpeggio's
# default; tests/test_tsm_reader.py compares them with the grammar's).
IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?![^\x00-\x7f])", re.MULTILINE)
ROS_TYPE = re.compile(r"[A-Za-z0-9_]+\/[A-Za-z0-9_.\-]+(?![^\x00-\x7f])", re.MULTILINE)
QUOTED_STRING = re.compile(r'"(\\["\\nt]|[^"\\\x00-\x1f\x7f])*"', re.MULTILINE)
INT = re.compile(r"[0-9]+(?![\w.])", re.MULTILINE)
BOOLEAN = re.compile(r"(true|false)(?![\w])", re.MULTILINE)
_NUMBER = r"(\d+\.\d*([eE][-+]?\d+)?|\.\d+([eE][-+]?\d+)?|\d+[eE][-+]?\d+|\d+)(?![\w.])"
UNSIGNED_NUMBER = re.compile(_NUMBER, re.MULTILINE)
SIGNED_NUMBER = re.compile(r"[-+]?" + _NUMBER, re.MULTILINE)
# What textX skips before every terminal: its whitespace (arpeggio's default), then the
# alternatives of the grammar's Comment rule, each followed by whitespace.
WHITESPACE = "\t\n\r "
COMMENTS = (r"\/\/[^\n]*", r"\/\*(.|\n)*?\*\/")
_SKIP = re.compile(rf"(?:[{WHITESPACE}]+|{COMMENTS[0]}|{COMMENTS[1]})*")
# A keyword ``kw`` (matched as ``kw\b``, textX's autokwd) is next exactly when the run
# of word characters there is ``kw``.
_WORD = re.compile(r"\w*")


def _rule(name: str, attributes: str) -> Any:
    """The class of a grammar rule's objects: its attributes, and where it starts."""
    base = namedtuple(name, "position " + attributes)
    return type(name, (base,), {"__slots__": (), "_tx_position": property(itemgetter(0))})


System = _rule("System", "name elements")
RobotContainer = _rule("RobotContainer", "name endpoint namespace members")
CloudContainer = _rule("CloudContainer", "name group size cpu memory bandwidth namespace members")
Endpoint = _rule("Endpoint", "robotId url user password")
EnvPassword = _rule("EnvPassword", "variable")
LiteralPassword = _rule("LiteralPassword", "literal")
Topic = _rule("Topic", "name type rosName")
Node = _rule("Node", "optional name sharing implementation args members")
Parameter = _rule("Parameter", "name type value")
StringValue = _rule("StringValue", "value")
BoolValue = _rule("BoolValue", "value")
NumberValue = _rule("NumberValue", "value")
Publishes = _rule("Publishes", "name type topic")
Subscribes = _rule("Subscribes", "name type topic")
Provides = _rule("Provides", "name type rosName")
Calls = _rule("Calls", "name type server")
Bridge = _rule("Bridge", "source target")
DataType = _rule("DataType", "name fields")
Field = _rule("Field", "name type")
Transform = _rule("Transform", "name input output assignments")
Assignment = _rule("Assignment", "field expression")
Store = _rule("Store", "optional name raw refinements")
Refinement = _rule("Refinement", "output transform period")
Period = _rule("Period", "value")
Writer = _rule("Writer", "optional name dataType store topic implementation args parameters")
Reader = _rule("Reader", "optional name dataType store topic period implementation args parameters")
OrExpr = _rule("OrExpr", "operands")
AndExpr = _rule("AndExpr", "operands")
NotOp = _rule("NotOp", "operand")
Comparison = _rule("Comparison", "left operator right")
Additive = _rule("Additive", "operands operators")
Multiplicative = _rule("Multiplicative", "operands operators")
Negation = _rule("Negation", "operand")
Postfix = _rule("Postfix", "primary indexes")
Index = _rule("Index", "index")
Parenthesized = _rule("Parenthesized", "inner")
NumberLiteral = _rule("NumberLiteral", "value")
BooleanLiteral = _rule("BooleanLiteral", "value")
StringLiteral = _rule("StringLiteral", "value")
Call = _rule("Call", "function arguments")
Reference = _rule("Reference", "parts")
Name = _rule("Name", "name")
Ref = _rule("Ref", "name")
QRef = _rule("QRef", "parts")
TypeRef = _rule("TypeRef", "value")
ImplRef = _rule("ImplRef", "value")
Str = _rule("Str", "value")
Int = _rule("Int", "value")


class Refused(Exception):
    """The reader does not take this text (textX parses it)."""


class Tokens:
    """One text read from the start; ``pos`` is where the next terminal is looked for.

    Every method that reads commits: where the text holds something else it raises
    :class:`Refused` (no backtracking, see ``spl.dsl.tsm_reader``)."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.pos = 0
        self._skipped = (-1, -1)  # the last skip: from, to

    # -- terminals -------------------------------------------------------------------
    def skip(self) -> int:
        """Where the next terminal starts: past blanks and comments."""
        start, end = self._skipped
        if start != self.pos:
            end = _SKIP.match(self.text, self.pos).end()
            self._skipped = (self.pos, end)
        return end

    def word(self) -> tuple[int, str]:
        """Where the next token starts, and its run of word characters ('' if none)."""
        at = self.skip()
        return at, _WORD.match(self.text, at).group()

    def keyword(self, keyword: str) -> int:
        at, word = self.word()
        if word != keyword:
            raise Refused
        self.pos = at + len(keyword)
        return at

    def at(self, literal: str) -> bool:
        return self.text.startswith(literal, self.skip())

    def punct(self, literal: str) -> int:
        at = self.skip()
        if not self.text.startswith(literal, at):
            raise Refused
        self.pos = at + len(literal)
        return at

    def match(self, regex: re.Pattern[str]) -> tuple[int, str]:
        at = self.skip()
        found = regex.match(self.text, at)
        if found is None:
            raise Refused
        self.pos = found.end()
        return at, found.group()

    def one_of(self, keywords: tuple[str, ...]) -> str:
        at, word = self.word()
        if word not in keywords:
            raise Refused
        self.pos = at + len(word)
        return word

    def name(self, rule: Any = Name) -> Any:
        return rule(*self.match(IDENT))

    def qref(self) -> Any:
        parts = [self.name()]
        while self.at("."):
            self.punct(".")
            parts.append(self.name())
        return QRef(parts[0].position, parts)

    def string(self) -> Any:
        return Str(*self.match(QUOTED_STRING))

    def optional_string(self, keyword: str) -> Any:
        """``(KEYWORD value=Str)?``"""
        at, word = self.word()
        if word != keyword:
            return None
        self.pos = at + len(keyword)
        return self.string()
