"""A statement's options, read from ``tsm.tx``: the ``('KEYWORD' attribute=Rule)?`` parts
that close a rule (a server's ``name "/ros/name"``, an input's ``external "why"``).

The grammar is the one source of a statement's syntax (docs/architecture.md, "Adding one
.tsm element, end to end"), so what the fast reader reads after a statement's shape, the
fields of its rule's class in the reader's tree, the value the builder copies into the
model and what the printer writes back are all made from these declarations: an option
added to a rule of ``tsm.tx`` whose attribute the metamodel declares under the same name
is read, checked by its type's range, built and printed without another edit.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from spl.dsl.grammar_text import Expr, rules
from spl.metamodels.interface_kinds import KINDS


@dataclass(frozen=True)
class Option:
    """One closing ``('KEYWORD' attribute=VALUE)?`` of a rule."""

    keyword: str
    attribute: str
    value: str  # the value's rule, one ``value=TERMINAL`` assignment (Str, Int, NumberLiteral)
    terminal: re.Pattern[str]  # what that rule matches, as textX compiles it

    @property
    def quoted(self) -> bool:
        """Whether the value is written as a double-quoted string (``Str``)."""
        return self.terminal.pattern.startswith('"')


def _option(part: Expr) -> tuple[str, str, str] | None:
    """``(keyword, attribute, value rule)`` of ``('KEYWORD' attribute=Rule)?``, else None."""
    if part[0] != "rep" or part[1] != "?" or part[2][0] != "seq" or len(part[2][1]) != 2:
        return None
    word, assignment = part[2][1]
    if word[0] != "str" or assignment[0] != "assign" or assignment[2] != "=":
        return None
    if assignment[3][0] != "ref":
        return None
    return word[1], assignment[1], assignment[3][1]


def _terminal(value_rule: str) -> re.Pattern[str]:
    """The regular expression of a rule of one ``value=TERMINAL`` assignment."""
    grammar = rules("tsm")
    body = grammar[value_rule]
    if body[0] != "assign" or body[1] != "value":
        raise ValueError(f"tsm.tx: option value {value_rule} is not one value=TERMINAL")
    matched = body[3]
    if matched[0] == "ref":
        matched = grammar[matched[1]]
    if matched[0] != "regex":
        raise ValueError(f"tsm.tx: option value {value_rule} matches no terminal")
    return re.compile(matched[1], re.MULTILINE)  # arpeggio's default flags


def options(rule: str) -> tuple[Option, ...]:
    """The options closing ``rule`` of ``tsm.tx``, in the grammar's order."""
    body = rules("tsm")[rule]
    parts = body[1] if body[0] == "seq" else (body,)
    found: list[Option] = []
    for part in reversed(parts):
        option = _option(part)
        if option is None:
            break
        keyword, attribute, value = option
        found.append(Option(keyword, attribute, value, _terminal(value)))
    return tuple(reversed(found))


# the options closing each interface statement, by its rule's name in tsm.tx: read by the
# fast reader, copied by the builder and written back by the printer
INTERFACE_OPTIONS: dict[str, tuple[Option, ...]] = {kind.rule: options(kind.rule) for kind in KINDS}
