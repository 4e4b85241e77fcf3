"""A fast reader of ``tsm.tx``: the parse tree textX makes, in a fraction of its time.

textX interprets the grammar one parsing expression at a time and builds a parse tree
before the model objects; on a 10,000-node .tsm file that is most of ``spl check``. This
reader follows ``tsm.tx`` rule by rule as a predictive recursive descent: at each choice
it looks at the next token (skipping blanks and comments exactly where textX does) and
commits to the one alternative that can start there. It returns objects with the class
names, attributes and ``_tx_position`` textX gives, so the builder cannot tell them apart.

Committing is safe because the reader only ever gives up where textX may go on: an
alternative is taken when its first token is next and every earlier alternative cannot
start there, so where the reader reads a text to its end, textX's ordered choices and
repetitions made the same choices. It never reports a problem itself: on anything it
does not read to the end (a syntax error, or an expression nested deeper than
``MAX_DEPTH``) it returns None and textX parses the text, so syntax errors, and the
refusal of expressions too deep for textX, stay exactly textX's. Where it reads a text,
textX reads the same tree (``tests/test_tsm_reader.py`` compares both on every shipped
model and mutations of them).

It pays (``bench/readers.py``, docs/performance.md "Fast readers", CPU time on a
loaded 2-core machine): the parse tree of the synthetic line of ``bench/tsm_scale.py``
in 0.060 s instead of textX's 1.63 s at 1,000 nodes (27x), of the shipped .tsm files
22x faster; ``spl check`` of the 1,000-node .tsm takes 0.27 s of CPU with it and
1.37 s without (5.1x), of the shipped mapping3d line 0.27 s and 0.36 s.
The editor's incremental reading (``tsm_incremental``) and the excerpts textX words
syntax errors from (``tsm_syntax_excerpt``) are built on it too. A keyword added to
``tsm.tx`` must be read here too: ``tests/test_grammar_keywords.py`` checks it.
"""

from __future__ import annotations

from typing import Any, cast

from spl.dsl.tsm.interface_reader import OPENED_BY, InterfaceReader
from spl.dsl.tsm.tree import (
    BOOLEAN,
    IDENT,
    INT,
    QUOTED_STRING,
    ROS_TYPE,
    SIGNED_NUMBER,
    UNSIGNED_NUMBER,
    Assignment,
    BoolValue,
    Bridge,
    CloudContainer,
    DataType,
    Endpoint,
    EnvPassword,
    Field,
    ImplRef,
    Int,
    LiteralPassword,
    Node,
    NumberValue,
    Parameter,
    Period,
    Reader,
    Refinement,
    Refused,
    RobotContainer,
    Store,
    StringValue,
    System,
    Topic,
    Transform,
    TypeRef,
    Writer,
)


def read(text: str) -> Any:
    """The textX parse tree of ``text`` (a ``System``), or None to leave it to textX."""
    try:
        return _Reader(text).system()
    except Refused:
        return None


class _Reader(InterfaceReader):
    """The declaration rules of the .tsm reader: the system, containers, nodes, bridges,
    data types, transforms and the data-acquisition nodes."""

    # -- the system and its containers -----------------------------------------------
    def system(self) -> Any:
        at, word = self.word()
        name = None
        if word == "system":
            self.pos = at + len(word)
            name = self.name()
        elements = self.by_keyword(_ELEMENTS)
        if self.skip() != len(self.text):
            raise Refused
        if name is None and not elements:
            raise Refused  # textX gives '' for text holding no element at all
        return System(at if name is not None else elements[0].position, name, elements)

    def by_keyword(self, rules: dict[str, Any]) -> list[Any]:
        """``(A | B | ...)*`` where each alternative starts with a keyword of its own."""
        found: list[Any] = []
        while True:
            at, word = self.word()
            rule = rules.get(word)
            if rule is None:
                return found
            found.append(self.item(rules, rule, at))

    def item(self, rules: dict[str, Any], rule: Any, at: int, *optional: bool) -> Any:
        """One element of a repetition of ``rules``, read by ``rule`` at ``at``: the
        place where an incremental reading (``spl.dsl.tsm.incremental``) takes the
        element of the previous reading instead."""
        return rule(self, at, *optional)

    def robot_container(self, start: int) -> Any:
        self.keyword("robot")
        self.keyword("container")
        name = self.name()
        self.punct("{")
        endpoint = self.endpoint() if self.word()[1] == "endpoint" else None
        namespace = self.optional_string("namespace")
        members = self.members()
        self.punct("}")
        return RobotContainer(start, name, endpoint, namespace, members)

    def cloud_container(self, start: int) -> Any:
        self.keyword("cloud")
        self.keyword("container")
        name = self.name()
        number = self.integer
        settings = self.unordered(
            {
                "group": self.string,
                "size": number,
                "cpu": number,
                "memory": number,
                "bandwidth": number,
            }
        )
        self.punct("{")
        namespace = self.optional_string("namespace")
        members = self.members()
        self.punct("}")
        group, size, cpu, memory, bandwidth = settings
        return CloudContainer(start, name, group, size, cpu, memory, bandwidth, namespace, members)

    def unordered(self, values: dict[str, Any]) -> list[Any]:
        """``( (KEYWORD value)? ... )#``: each at most once, in any order."""
        found = dict.fromkeys(values)
        remaining = set(values)
        while True:
            at, word = self.word()
            if word not in remaining:
                return list(found.values())
            remaining.remove(word)
            self.pos = at + len(word)
            found[word] = values[word]()

    def integer(self) -> Any:
        return Int(*self.match(INT))

    def endpoint(self) -> Any:
        start = self.keyword("endpoint")
        text = self.string
        settings = self.unordered(
            {"robot_id": text, "url": text, "user": text, "password": self.password}
        )
        return Endpoint(start, *settings)

    def password(self) -> Any:
        at, word = self.word()
        if word == "env":
            self.pos = at + len(word)
            return EnvPassword(at, self.string())
        value = self.string()
        return LiteralPassword(value.position, value)

    def members(self) -> list[Any]:
        members: list[Any] = []
        while True:
            start, word = self.word()
            optional = word == "optional"
            if optional:
                self.pos = start + len(word)
                word = self.word()[1]
            member = _MEMBERS.get(word)
            if member is None or (optional and word == "topic"):
                self.pos = start
                return members
            members.append(self.item(_MEMBERS, member, start, optional))

    def topic(self, start: int, optional: bool) -> Any:
        self.keyword("topic")
        name = self.name()
        self.punct(":")
        kind = TypeRef(*self.match(ROS_TYPE))
        return Topic(start, name, kind, self.optional_string("name"))

    # -- nodes -------------------------------------------------------------------------
    def node(self, start: int, optional: bool) -> Any:
        self.keyword("node")
        name = self.name()
        sharing = None
        at, word = self.word()
        if word == "sharing":
            self.pos = at + len(word)
            sharing = self.one_of(("private", "protected", "public"))
        self.punct("{")
        implementation, args = self.implementation()
        members = self.by_keyword(_NODE_MEMBERS)
        self.punct("}")
        return Node(start, optional, name, sharing, implementation, args, members)

    def implementation(self) -> tuple[Any, Any]:
        """``('implementation' implementation=ImplRef ('args' args=Str)?)?``"""
        at, word = self.word()
        if word != "implementation":
            return None, None
        self.pos = at + len(word)
        implementation = ImplRef(*self.match(ROS_TYPE))
        return implementation, self.optional_string("args")

    def parameter(self, start: int) -> Any:
        self.keyword("param")
        name = self.name()
        self.punct(":")
        kind = self.one_of(("string", "int", "double", "bool", "yaml"))
        value: StringValue | BoolValue | NumberValue | None = None
        if self.at("="):
            self.punct("=")
            at = self.skip()
            if QUOTED_STRING.match(self.text, at):
                value = StringValue(at, self.string())
            elif BOOLEAN.match(self.text, at):
                value = BoolValue(*self.match(BOOLEAN))
            else:
                value = NumberValue(*self.match(SIGNED_NUMBER))
        return Parameter(start, name, kind, value)

    def bridge(self, start: int) -> Any:
        self.keyword("bridge")
        source = self.qref()
        self.punct("->")
        return Bridge(start, source, self.qref())

    # -- data acquisition --------------------------------------------------------------
    def data_type(self, start: int) -> Any:
        self.keyword("data")
        name = self.name()
        return DataType(start, name, self.entries(":", Field, self.field_type))

    def field_type(self) -> str:
        return self.one_of(("double", "int", "string", "bool"))

    def entries(self, separator: str, rule: Any, value: Any) -> list[Any]:
        """``'{' (NAME SEPARATOR VALUE)* '}'``: a data type's fields, a transform's
        assignments."""
        self.punct("{")
        found = []
        while IDENT.match(self.text, self.skip()):
            name = self.name()
            self.punct(separator)
            found.append(rule(name.position, name, value()))
        self.punct("}")
        return found

    def transform(self, start: int) -> Any:
        self.keyword("transform")
        name = self.name()
        self.punct(":")
        source = self.ref()
        self.punct("->")
        target = self.ref()
        return Transform(
            start, name, source, target, self.entries("=", Assignment, self.expression)
        )

    def store(self, start: int, optional: bool) -> Any:
        self.keyword("store")
        name = self.name()
        self.punct("{")
        self.keyword("raw")
        raw = self.ref()
        refinements = []
        while self.word()[1] == "refined":
            at = self.keyword("refined")
            output = self.ref()
            self.keyword("by")
            transform = self.ref()
            self.keyword("every")
            refinements.append(Refinement(at, output, transform, self.period()))
        self.punct("}")
        return Store(start, optional, name, raw, refinements)

    def period(self) -> Any:
        period = Period(*self.match(UNSIGNED_NUMBER))
        self.keyword("s")
        return period

    def writer(self, start: int, optional: bool) -> Any:
        return self.data_node(start, optional, "writer", "to", "<-")

    def reader(self, start: int, optional: bool) -> Any:
        return self.data_node(start, optional, "reader", "from", "->")

    def data_node(self, start: int, optional: bool, keyword: str, way: str, arrow: str) -> Any:
        """Writer and Reader: ``KEYWORD name ':' Ref WAY QRef ARROW Ref`` [every] [block]."""
        self.keyword(keyword)
        name = self.name()
        self.punct(":")
        data_type = self.ref()
        self.keyword(way)
        store = self.qref()
        self.punct(arrow)
        topic = self.ref()
        period, subscribe = None, False
        if keyword == "reader":
            subscribe = self.word()[1] == "subscribe"
            if subscribe:
                self.keyword("subscribe")
            self.keyword("every")
            period = self.period()
        implementation = args = None
        parameters = []
        if self.at("{"):
            self.punct("{")
            implementation, args = self.implementation()
            while self.word()[1] == "param":
                parameters.append(self.parameter(self.skip()))
            self.punct("}")
        head = (start, optional, name, data_type, store, topic)
        if keyword == "reader":
            every = cast(Period, period)  # a reader's: read above
            return Reader(*head, subscribe, every, implementation, args, parameters)
        return Writer(*head, implementation, args, parameters)


_ELEMENTS = {
    "data": _Reader.data_type,
    "transform": _Reader.transform,
    "robot": _Reader.robot_container,
    "cloud": _Reader.cloud_container,
    "bridge": _Reader.bridge,
}
_MEMBERS = {
    "topic": _Reader.topic,
    "node": _Reader.node,
    "writer": _Reader.writer,
    "reader": _Reader.reader,
    "store": _Reader.store,
}
# A node's parameters, and the interface statements of the registry's kinds by the word
# that opens each (interface_reader.OPENED_BY).
_NODE_MEMBERS = {"param": _Reader.parameter, **dict.fromkeys(OPENED_BY, _Reader.interface)}
