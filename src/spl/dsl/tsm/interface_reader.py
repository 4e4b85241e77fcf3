"""The fast reader's statements of a node's interfaces, one per kind of ``tsm.tx``
(``Publishes``, ``Subscribes``, ``ProvidesAction``, ``Provides``, ``CallsAction``,
``Calls``; docs/architecture.md, "Interface kinds"), read as textX reads them
(``spl.dsl.tsm.reader`` says how, and when it leaves a text to textX).
"""

from __future__ import annotations

from typing import Any

from spl.dsl.tsm.expression_reader import ExpressionReader
from spl.dsl.tsm.tree import (
    IDENT,
    ROS_TYPE,
    Calls,
    CallsAction,
    Provides,
    ProvidesAction,
    Publishes,
    Ref,
    Subscribes,
    TypeRef,
)


class InterfaceReader(ExpressionReader):
    """``publishes``, ``subscribes``, ``provides [action]`` and ``calls [action]``."""

    def publishes(self, start: int) -> Any:
        return self.interface(start, "publishes", Publishes, "->", self.ref)

    def subscribes(self, start: int) -> Any:
        return self.interface(start, "subscribes", Subscribes, "<-", self.ref)

    def calls(self, start: int) -> Any:
        return self.interface(start, "calls", Calls, "->", self.qref, CallsAction)

    def action(self) -> bool:
        """Whether ``action NAME`` is next, then read up to the name: textX tries the
        action statement first (tsm.tx, ``NodeMember``) and it fails before the name
        where ``action`` is a service's or client's own name (``provides action : T``)."""
        start = self.pos
        if self.word()[1] == "action":
            self.keyword("action")
            if IDENT.match(self.text, self.skip()):
                return True
        self.pos = start
        return False

    def interface(
        self, start: int, keyword: str, rule: Any, arrow: str, target: Any, action: Any = None
    ) -> Any:
        """``KEYWORD name ((':' TypeRef (ARROW TARGET)?) | (ARROW TARGET)) ('external'
        Str)?``, or the ``action`` rule's ``KEYWORD 'action' name ...``."""
        self.keyword(keyword)
        if action is not None and self.action():
            rule = action
        name = self.name()
        kind = found = None
        if self.at(":"):
            self.punct(":")
            kind = TypeRef(*self.match(ROS_TYPE))
            if self.at(arrow):
                self.punct(arrow)
                found = target()
        else:
            self.punct(arrow)
            found = target()
        if rule is Publishes:
            return rule(start, name, kind, found)
        return rule(start, name, kind, found, self.optional_string("external"))

    def ref(self) -> Any:
        return self.name(Ref)

    def provides(self, start: int) -> Any:
        self.keyword("provides")
        rule = ProvidesAction if self.action() else Provides
        name = self.name()
        self.punct(":")
        kind = TypeRef(*self.match(ROS_TYPE))
        return rule(start, name, kind, self.optional_string("name"))
