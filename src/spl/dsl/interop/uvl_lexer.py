"""The UVL lexer: text -> tokens, exactly as the reference grammar's Python lexer makes them.

uvlparser's lexer (``UVLLexer.g4`` with the Python target's indentation handling) turns
line breaks into NEWLINE tokens except inside brackets and before blank or comment
lines, and changes of indentation into INDENT/DEDENT (tabs count to the next multiple
of 8). :func:`tokenize` does the same with one regular expression over the whole text,
so the reader (:mod:`spl.dsl.interop.uvl_reader`) can follow the grammar rule by rule.
"""

from __future__ import annotations

import re

# One alternative per token of UVLLexer.g4, ordered so the first match is ANTLR's
# longest match; blanks and comments before a token are skipped like the lexer's SKIP_
# rule (as a prefix of the next token: half as many matches to loop over). A block
# comment runs to the *last* "*/" of the file, as in the grammar (its ".*" is greedy):
# flamapy and every tool on uvlparser read such a file so, and spl reads the same model.
# "end" matches only at the end of the text, so a trailing comment is never given back.
_TOKEN = re.compile(
    r"""
    (?:[ \t]|//[^\n]*|/\*.*\*/)*
    (?:
      (?P<nl>\n[ \t]*)
    | (?P<card>\[(?:0|-?[1-9][0-9]*)(?:\.\.(?:0|-?[1-9][0-9]*|\*))?\])
    | (?P<float>-?[0-9]*\.[0-9]+)
    | (?P<int>0|-?[1-9][0-9]*)
    | (?P<word>[a-zA-Z][a-zA-Z0-9_\#§%?\\'äüöß;]*)
    | (?P<qid>"[^\n".]+")
    | (?P<string>'[^\n']+')
    | (?P<op><=>|=>|==|<=|>=|!=|[!&|<>/*+\-(){}\[\],.])
    | (?P<bad>[^ \t])
    | (?P<end>\Z)
    )
    """,
    re.VERBOSE | re.DOTALL,
)
_KIND_OF_GROUP = {index: name for name, index in _TOKEN.groupindex.items()}
# Words the lexer makes keywords (a feature spelled like one must be quoted).
KEYWORDS = frozenset(
    (
        "include",
        "features",
        "imports",
        "namespace",
        "as",
        "constraint",
        "constraints",
        "cardinality",
        "String",
        "Boolean",
        "Integer",
        "Real",
        "len",
        "sum",
        "avg",
        "floor",
        "ceil",
        "Type",
        "Arithmetic",
        "or",
        "alternative",
        "optional",
        "mandatory",
        "true",
        "false",
    )
)
_WORD_KINDS = {word: word for word in KEYWORDS} | {"true": "bool", "false": "bool"}
OPENING = {"(": 1, "[": 1, "{": 1, ")": -1, "]": -1, "}": -1}


def tokenize(text: str) -> list[tuple[str, str, int]]:
    """``(kind, text, offset)`` tokens with NEWLINE/INDENT/DEDENT as the Python lexer
    makes them: kind is the keyword or operator itself, or id, qid (quoted name), bool,
    int, float, string, card (a group cardinality ``[n..m]``), bad (no token), NL,
    INDENT, DEDENT, EOF."""
    tokens: list[tuple[str, str, int]] = []
    append = tokens.append
    indents: list[int] = []
    opened = 0
    size = len(text)
    if text[:1] in (" ", "\t"):  # the lexer treats blanks at the very start as a line break
        text = "\n" + text
        shift = -1
    else:
        shift = 0
    kinds = _KIND_OF_GROUP
    for match in _TOKEN.finditer(text):
        group = match.lastindex  # one group of the alternatives matched
        value = match[group]  # type: ignore[index]
        kind = kinds[group]  # type: ignore[index]
        end = match.end() + shift
        start = end - len(value)
        if kind == "word":
            kind = _WORD_KINDS.get(value, "id")
        elif kind == "end":  # blanks or a comment at the very end: nothing to take back
            break
        elif kind == "op":
            kind = value
            opened += OPENING.get(value, 0)
        elif kind == "nl":
            following = text[match.end() : match.end() + 1]
            if opened > 0 or following in ("", "\n", "/", "#"):
                continue
            append(("NL", "", max(start, 0)))
            indent = len(value[1:].expandtabs(8))
            previous = indents[-1] if indents else 0
            if indent > previous:
                indents.append(indent)
                append(("INDENT", "", end))
            elif indent < previous:
                while indents and indents[-1] > indent:
                    indents.pop()
                    append(("DEDENT", "", end))
            continue
        append((kind, value, start))
    if indents:
        append(("NL", "", size))
        tokens.extend([("DEDENT", "", size)] * len(indents))
    append(("EOF", "", size))
    return tokens
