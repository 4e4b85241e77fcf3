"""Positions: spl's ``file:line:col`` (1-based, columns in characters) and the
Language Server Protocol's (0-based, columns in the negotiated code units, UTF-16
unless the client offers another).

A column is a count of characters in spl (textX counts code points) and of UTF-16
code units in most editors: a character outside the Basic Multilingual Plane (an
emoji in a comment) is one column for spl and two for VS Code, so every position
crossing the protocol goes through :class:`LineIndex`.
"""

from __future__ import annotations

import re
from bisect import bisect_right

from lsprotocol import types

UTF8, UTF16, UTF32 = "utf-8", "utf-16", "utf-32"
_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*|[^\s]")


def units(text: str, encoding: str) -> int:
    """The length of ``text`` in the code units of ``encoding``."""
    if encoding == UTF32:
        return len(text)
    if encoding == UTF8:
        return len(text.encode("utf-8", "surrogatepass"))
    return len(text) + sum(1 for c in text if ord(c) > 0xFFFF)


class LineIndex:
    """Offsets of one text's lines, to move between character offsets, spl's
    (line, col) and LSP positions. Lines end at ``\\n``, as textX counts them."""

    def __init__(self, text: str, encoding: str = UTF16) -> None:
        self.text = text
        self.encoding = encoding
        self.starts = [0] + [m.end() for m in re.finditer("\n", text)]

    def line_text(self, line: int) -> str:
        """Line ``line`` (0-based) without its line break."""
        if not 0 <= line < len(self.starts):
            return ""
        end = self.starts[line + 1] - 1 if line + 1 < len(self.starts) else len(self.text)
        return self.text[self.starts[line] : end].removesuffix("\r")

    def position(self, offset: int) -> types.Position:
        """The LSP position of character ``offset``."""
        offset = max(0, min(offset, len(self.text)))
        line = bisect_right(self.starts, offset) - 1
        before = self.text[self.starts[line] : offset]
        return types.Position(line=line, character=units(before, self.encoding))

    def offset(self, position: types.Position) -> int:
        """The character offset of an LSP position (clamped to the text)."""
        if position.line >= len(self.starts):
            return len(self.text)
        line = self.line_text(position.line)
        count = 0
        for index, char in enumerate(line):
            if count >= position.character:
                return self.starts[position.line] + index
            count += units(char, self.encoding)
        return self.starts[position.line] + len(line)

    def spl_offset(self, line: int, col: int) -> int:
        """The character offset of spl's 1-based ``line:col`` (0 means the start)."""
        if line < 1:
            return 0
        if line > len(self.starts):
            return len(self.text)
        return min(self.starts[line - 1] + max(col - 1, 0), len(self.text))

    def spl_place(self, offset: int) -> tuple[int, int]:
        """spl's 1-based (line, col) of character ``offset``."""
        line = bisect_right(self.starts, offset) - 1
        return line + 1, offset - self.starts[line] + 1

    def range(self, start: int, end: int) -> types.Range:
        return types.Range(start=self.position(start), end=self.position(end))

    def word_range(self, line: int, col: int) -> types.Range:
        """The range of the word (or the one character) spl's ``line:col`` points at:
        what an editor underlines for a diagnostic located there."""
        start = self.spl_offset(line, col)
        line_end = self.text.find("\n", start)
        line_end = len(self.text) if line_end < 0 else line_end
        match = _WORD.match(self.text, start, line_end)
        end = match.end() if match else start
        return self.range(start, end)
