"""textX grammars (``dsl/*.tx``) read as rules and expressions, without textX: a small
parser of textX's grammar language (rules, sequences, ordered choices, groups,
repetitions, assignments, string and regex matches, imports), for
:mod:`spl.dsl.grammar_keywords`, which derives the languages' keywords from it.
Building textX's metamodel costs a tenth of a second and more, this a millisecond.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping
from functools import cache
from pathlib import Path

# An expression of a rule's body, as nested tuples:
#   ("str", text) ("regex", pattern) ("ref", rule) ("seq", (e, ...)) ("choice", (e, ...))
#   ("rep", "?" | "*" | "+" | "#", e) ("assign", attribute, "=" | "+=" | "*=" | "?=", e)
#   ("pred", "&" | "!", e)
Expr = tuple

_TOKEN = re.compile(
    r"""
    (?P<skip>\s+|//[^\n]*|/\*.*?\*/)
  | (?P<str>'(?:\\.|[^'\\])*'|"(?:\\.|[^"\\])*")
  | (?P<regex>/(?:\\.|[^/\\\n])+/)
  | (?P<name>[A-Za-z_][A-Za-z0-9_.]*)
  | (?P<op>\?=|\+=|\*=|[=:;|()\[\]?*+#&!,-])
    """,
    re.VERBOSE | re.DOTALL,
)
_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
# /(w1|w2)(?!...)/: a terminal matching one of a few words
LITERAL_WORDS = re.compile(r"\(((?:[A-Za-z_]\w*\|)*[A-Za-z_]\w*)\)(?=\(\?!|\Z)")
# /(?!(w1|w2)(?!...))NAME/: a name that may not be one of a few words
EXCLUDED_WORDS = re.compile(r"\(\?!\(((?:[A-Za-z_]\w*\|)*[A-Za-z_]\w*)\)")
_UNESCAPE = re.compile(r"\\(.)")
# where each grammar is: beside its language's package (the .fm imports capability.tx)
GRAMMARS = {
    name: Path(__file__).parent / folder / f"{name}.tx"
    for name, folder in (("tsm", "tsm"), ("fm", "fm"), ("capability", "fm"), ("rm", "rm"))
}
# textX's own rules (terminals, none a keyword of spl's languages)
BUILT_IN = frozenset({"ID", "BOOL", "INT", "FLOAT", "STRICTFLOAT", "STRING", "NUMBER", "BASETYPE"})


def is_word(text: str) -> bool:
    """Whether a string match is a word (a keyword), not punctuation."""
    return bool(_WORD.match(text))


# -- reading a grammar ---------------------------------------------------------------------
def _tokens(text: str) -> list[tuple[str, str]]:
    """The tokens of a grammar's text, blanks and comments left out, and an end mark."""
    tokens, covered = [], 0
    for match in _TOKEN.finditer(text):
        covered += match.end() - match.start()
        if match.lastgroup != "skip":
            tokens.append((match.lastgroup or "", match.group()))
    if covered != len(text):
        raise ValueError("not a textX grammar this reader knows")
    tokens.append(("end", ""))
    return tokens


class _Parser:
    """textX's grammar language, from one token on: a rule's body (``choice``)."""

    def __init__(self, tokens: list[tuple[str, str]], at: int = 0) -> None:
        self.tokens = tokens
        self.at = at

    def peek(self, offset: int = 0) -> tuple[str, str]:
        return self.tokens[min(self.at + offset, len(self.tokens) - 1)]

    def take(self, text: str | None = None) -> str:
        kind, value = self.tokens[self.at]
        if kind == "end" or (text is not None and value != text):
            raise ValueError(f"grammar: expected {text or 'a token'}, found {value!r}")
        self.at += 1
        return value

    def choice(self) -> Expr:
        alternatives = [self.sequence()]
        while self.tokens[self.at][1] == "|":
            self.at += 1
            alternatives.append(self.sequence())
        return alternatives[0] if len(alternatives) == 1 else ("choice", tuple(alternatives))

    def sequence(self) -> Expr:
        elements = []
        while self.tokens[self.at][1] not in ("|", ")", ";", ""):
            elements.append(self.repeatable())
        return elements[0] if len(elements) == 1 else ("seq", tuple(elements))

    def repeatable(self) -> Expr:
        expr = self.expression()
        if self.tokens[self.at][1] in ("?", "*", "+", "#"):
            expr = ("rep", self.take(), expr)
            self.modifiers()
        if self.tokens[self.at][1] == "-":  # suppression
            self.at += 1
        return expr

    def modifiers(self) -> None:
        """Repetition modifiers (``[',']``, ``[eolterm]``): they add no keyword."""
        if self.tokens[self.at][1] == "[":
            while self.take() != "]":
                pass

    def expression(self) -> Expr:
        kind, value = self.tokens[self.at]
        if value in ("&", "!"):
            self.at += 1
            return ("pred", value, self.expression())
        if kind == "name" and self.peek(1)[1] in ("=", "+=", "*=", "?="):
            self.at += 1
            operator = self.take()
            expr = self.simple()
            self.modifiers()
            return ("assign", value, operator, expr)
        return self.simple()

    def simple(self) -> Expr:
        kind, value = self.tokens[self.at]
        self.take()
        if kind == "str":
            return ("str", _UNESCAPE.sub(r"\1", value[1:-1]))
        if kind == "regex":
            return ("regex", value[1:-1])
        if kind == "name":
            return ("ref", value.rsplit(".", 1)[-1])
        if value == "(":
            expr = self.choice()
            self.take(")")
            return expr
        if value == "[":  # a cross reference [Class] or [Class:Rule]: no keyword either
            while self.take() != "]":
                pass
            return ("regex", "")
        raise ValueError(f"grammar: unexpected {value!r}")


class _Rules(Mapping[str, Expr]):
    """The rules of one grammar file and those it imports (name -> body); a body is
    parsed when it is first asked for (most uses need a few rules of a grammar)."""

    def __init__(self, language: str) -> None:
        text = GRAMMARS[language].read_text(encoding="utf-8")
        self.tokens = tokens = _tokens(text)
        parser = _Parser(tokens)
        self.imported: list[Mapping[str, Expr]] = []
        while parser.peek()[1] in ("import", "reference"):
            parser.take()
            self.imported.append(rules(parser.take()))
            if parser.peek()[1] == "as":
                parser.take()
                parser.take()
        self.spans: dict[str, int] = {}  # a rule's name -> the first token of its body
        at = parser.at
        while tokens[at][0] != "end":
            name = tokens[at][1]
            at += 1
            if tokens[at][1] == "[":  # rule parameters, e.g. [noskipws]
                while tokens[at][1] != "]":
                    at += 1
                at += 1
            if tokens[at][1] != ":":
                raise ValueError(f"{language}.tx: expected ':' after {name}")
            self.spans[name] = at + 1
            while tokens[at][1] != ";":  # ';' ends a rule and appears nowhere else
                if tokens[at][0] == "end":
                    raise ValueError(f"{language}.tx: rule {name} has no ';'")
                at += 1
            at += 1
        self.parsed: dict[str, Expr] = {}
        self.names = list(dict.fromkeys([n for m in self.imported for n in m] + [*self.spans]))

    def __getitem__(self, name: str) -> Expr:
        if name in self.parsed:
            return self.parsed[name]
        if name in self.spans:
            parser = _Parser(self.tokens, self.spans[name])
            body = parser.choice()
            parser.take(";")
            self.parsed[name] = body
            return body
        for imported in self.imported:
            if name in imported:
                return imported[name]
        raise KeyError(name)

    def __contains__(self, name: object) -> bool:
        return name in self.spans or any(name in m for m in self.imported)

    def __iter__(self) -> Iterator[str]:
        return iter(self.names)

    def __len__(self) -> int:
        return len(self.names)


@cache
def rules(language: str) -> Mapping[str, Expr]:
    """Every rule of ``dsl/<language>.tx`` and of the grammars it imports (name -> body)."""
    return _Rules(language)


# -- what the rules say --------------------------------------------------------------------
