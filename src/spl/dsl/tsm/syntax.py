"""The lexical side of the .tsm language: syntax errors and the grammar's strings.

textX reports a syntax error as the grammar rules it expected; a user thinks in words
("a name", "a string"), so the rule names of ``tsm.tx`` are translated here, and a
letter look-alike from another script is named with its code point instead of being
reported as an unexpected token. Strings keep their quotes and escapes in the parse
tree; :func:`decode` gives their content.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

from spl.core.diagnostics import Diagnostic, Location
from spl.dsl.grammar_comments import is_comment

if TYPE_CHECKING:
    from textx import TextXSyntaxError

_RULE_WORDS = {
    "Ident": "a name",
    "RosType": "a type package/Type",
    "QuotedString": 'a string "..."',
    "UnsignedNumber": "a number",
    "SignedNumber": "a number",
    "Boolean": "true or false",
    "EOF": "end of file",  # arpeggio's EndOfFile prints as an object and its address
}


def syntax_diagnostic(exc: TextXSyntaxError, text: str, filename: str) -> Diagnostic:
    """The located ``syntax error: expected ..., found ...`` of a textX syntax error."""
    line, col = exc.line or 1, exc.col or 1
    offset = _offset(text, line, col)
    token = re.match(r"\S{0,30}", text[offset:]).group(0) if offset < len(text) else ""  # type: ignore[union-attr]
    foreign = next((i for i, ch in enumerate(token) if ord(ch) > 0x7F), None)
    if foreign is not None:
        ch = token[foreign]
        return Diagnostic(
            Location(filename, line, col + foreign),
            f"syntax error: character {ch!r} (U+{ord(ch):04X}) is not allowed here; "
            "names are ASCII identifiers [A-Za-z_][A-Za-z0-9_]*",
        )
    words = []
    for rule in exc.expected_rules or []:
        if is_comment(rule):
            continue
        name = getattr(rule, "rule_name", "") or ""
        word = _RULE_WORDS.get(name)
        if word is None:
            literal = getattr(rule, "to_match", None) or str(rule)
            word = f"'{literal}'"
        if word not in words:
            words.append(word)
    expected = ", ".join(sorted(words)) or "something else"
    shown = token if token.isprintable() else token.encode("unicode_escape").decode("ascii")
    found = f"'{shown}'" if token else "end of file"
    return Diagnostic(
        Location(filename, line, col), f"syntax error: expected {expected}, found {found}"
    )


def _offset(text: str, line: int, col: int) -> int:
    lines = text.split("\n")
    return sum(len(x) + 1 for x in lines[: line - 1]) + col - 1


def decode(quoted: str) -> str:
    """The content of a grammar string: the grammar allows only \\" \\\\ \\n \\t escapes."""
    escapes = {'"': '"', "\\": "\\", "n": "\n", "t": "\t"}
    return re.sub(r"\\(.)", lambda m: escapes[m.group(1)], quoted[1:-1])


def kind(tree: Any) -> str:
    """The grammar rule a parse-tree object was made by (textX names its class so)."""
    return type(tree).__name__
