"""The words of a model text as an editor sees them while it is being typed.

Navigation, completion and hover work on half-typed files that textX refuses, so
they read the text with this small lexer instead of the grammars: names (dotted
names keep their parts), strings, ROS types (``pkg/Type``), numbers and
punctuation, with comments skipped. The three languages share these lexical rules
(dsl/*.tx); a keyword is a name token whose text is a keyword of its language.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cached_property

from spl.lsp.positions import UTF16, LineIndex

_LEXER = re.compile(
    r"""
    (?P<comment>//[^\n]*|/\*(?:.|\n)*?(?:\*/|\Z))
  | (?P<string>"(?:\\.|[^"\\\n])*"?)
  | (?P<type>[A-Za-z0-9_]+/[A-Za-z0-9_.\-]*)
  | (?P<number>[-+]?(?:\d+\.(?!\.)\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?)
  | (?P<name>[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*)
  | (?P<punct><=>|=>|->|<-|<=|>=|==|!=|\.\.|[{}()\[\],:;=.<>+\-*/%!&|])
  | (?P<space>\s+)
  | (?P<other>.)
    """,
    re.VERBOSE,
)


@dataclass(frozen=True)
class Token:
    kind: str  # name, string, type, number, punct, other
    text: str
    start: int  # character offset in the text
    end: int

    @property
    def parts(self) -> list[str]:
        """The dotted parts of a name token."""
        return self.text.split(".")

    def part_spans(self) -> list[tuple[int, int]]:
        """The (start, end) offsets of each dotted part."""
        spans, position = [], self.start
        for part in self.parts:
            spans.append((position, position + len(part)))
            position += len(part) + 1
        return spans

    def part_at(self, offset: int) -> int:
        """The index of the part holding (or ending at) ``offset``."""
        for index, (start, end) in enumerate(self.part_spans()):
            if start <= offset <= end:
                return index
        return len(self.parts) - 1

    def is_word(self, *words: str) -> bool:
        return self.kind == "name" and self.text in words

    @property
    def string_value(self) -> str:
        return self.text[1:-1] if self.text.endswith('"') and len(self.text) > 1 else self.text[1:]


@dataclass
class Tokens:
    """The tokens of one text, with the index that maps offsets to positions."""

    text: str
    tokens: list[Token]
    encoding: str = UTF16

    @cached_property
    def lines(self) -> LineIndex:
        return LineIndex(self.text, self.encoding)

    def at(self, offset: int) -> int | None:
        """The index of the token holding ``offset`` (or ending right at it)."""
        low, high = 0, len(self.tokens)
        while low < high:
            middle = (low + high) // 2
            if self.tokens[middle].end < offset:
                low = middle + 1
            else:
                high = middle
        if low < len(self.tokens) and self.tokens[low].start <= offset <= self.tokens[low].end:
            return low
        return None

    def before(self, offset: int) -> list[Token]:
        """The tokens that end at or before ``offset``."""
        return [t for t in self.tokens if t.end <= offset]


def tokenize(text: str, encoding: str = UTF16) -> Tokens:
    """Every token of ``text`` but comments and blanks; never fails."""
    found = []
    for match in _LEXER.finditer(text):
        kind = match.lastgroup or "other"
        if kind in ("comment", "space"):
            continue
        found.append(Token(kind, match.group(), match.start(), match.end()))
    return Tokens(text, found, encoding)


def has_comments(text: str) -> bool:
    """Whether ``text`` holds a comment (the printers do not keep comments)."""
    return any(m.lastgroup == "comment" for m in _LEXER.finditer(text))
