"""The fast reader's statements of a node's interfaces, read as textX reads them
(``spl.dsl.tsm.reader`` says how, and when it leaves a text to textX).

Every interface statement of ``tsm.tx`` has one of three shapes, and its kind in the
registry says which (docs/architecture.md, "Interface kinds"): a server is bound to
nothing (``KEYWORD name ':' TypeRef ('name' Str)?``); any other kind names what it is
bound to after its arrow, a topic of its container or ``NODE.SERVER``
(``KEYWORD name ((':' TypeRef (ARROW TARGET)?) | (ARROW TARGET))``), and an input of
those may say what feeds it from outside (``('external' Str)?``). So a kind's statement
is read from its registry entry (its keyword, rule, arrow and side), into the class
``tree.py`` makes of the kind's rule, and a new kind needs nothing here. The options
closing a statement (``('name' rosName=Str)?``, ``('external' external=Str)?``, ...) are
read as its rule in ``tsm.tx`` declares them (``spl.dsl.tsm.options``), so an option
added there needs nothing here either.
"""

from __future__ import annotations

import re
from typing import Any

from spl.dsl.tsm import tree
from spl.dsl.tsm.expression_reader import ExpressionReader
from spl.dsl.tsm.options import INTERFACE_OPTIONS
from spl.dsl.tsm.tree import IDENT, ROS_TYPE, Ref, TypeRef
from spl.metamodels.interface_kinds import KINDS, InterfaceKind

# The options closing a statement: each one's keyword, its value's class in the reader's
# tree and the terminal that value is read with.
Options = tuple[tuple[str, Any, re.Pattern[str]], ...]
# The kinds whose statement a word opens, each with the words of its keyword after that
# one, its rule's class in the reader's tree and its options, the longer keywords first:
# textX tries an action statement before the service's (tsm.tx, ``NodeMember``).
OPENED_BY: dict[str, list[tuple[InterfaceKind, list[str], Any, Options]]] = {}
for _kind in sorted(KINDS, key=lambda k: -len(k.keyword.split())):
    _first, *_rest = _kind.keyword.split()
    _options = tuple(
        (o.keyword, getattr(tree, o.value), o.terminal) for o in INTERFACE_OPTIONS[_kind.rule]
    )
    OPENED_BY.setdefault(_first, []).append(
        (_kind, _rest, tree.INTERFACE_RULES[_kind.rule], _options)
    )


class InterfaceReader(ExpressionReader):
    """A node's interface statements, one rule per kind of the registry."""

    def interface(self, start: int) -> Any:
        """The statement at ``start``, of the first kind whose keyword it begins with."""
        kind, rule, closing = self.opened_kind()
        name = self.name()
        if kind.binds is None:
            self.punct(":")
            served = TypeRef(*self.match(ROS_TYPE))
            return rule(start, name, served, *self.options(closing))
        arrow = kind.arrow or ""
        target = self.ref if kind.on_topic else self.qref
        kind_type: TypeRef | None = None
        found = None
        if self.at(":"):
            self.punct(":")
            kind_type = TypeRef(*self.match(ROS_TYPE))
            if self.at(arrow):
                self.punct(arrow)
                found = target()
        else:
            self.punct(arrow)
            found = target()
        return rule(start, name, kind_type, found, *self.options(closing))

    def options(self, closing: Options) -> list[Any]:
        """``('KEYWORD' attribute=VALUE)?`` for each option, in the grammar's order."""
        found = []
        for keyword, value, terminal in closing:
            at, word = self.word()
            if word == keyword:
                self.pos = at + len(keyword)
                found.append(value(*self.match(terminal)))
            else:
                found.append(None)
        return found

    def opened_kind(self) -> tuple[InterfaceKind, Any, Options]:
        """The kind whose keyword comes next, and its rule's class, read up to the name: a
        keyword of several words (``provides action``) is one only where a name follows
        it, as textX's statement fails before the name where ``action`` is a service's
        own name (``provides action : T``)."""
        at, first = self.word()
        for kind, rest, rule, closing in OPENED_BY[first]:
            self.pos = at + len(first)
            for word in rest:
                word_at, found = self.word()
                if found != word:
                    break
                self.pos = word_at + len(word)
            else:  # a one-word keyword is the last tried: its name is read next
                if not rest or IDENT.match(self.text, self.skip()):
                    return kind, rule, closing
        raise tree.Refused

    def ref(self) -> Any:
        return self.name(Ref)
