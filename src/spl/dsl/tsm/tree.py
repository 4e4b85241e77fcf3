"""The parse tree of ``tsm.tx`` as textX shapes it, and the terminals it is read from.

One class per grammar rule, named after it, holding the rule's attributes (``None``,
``False`` or ``[]`` where textX leaves them unset) and ``_tx_position``, the offset of
its first token: the builder (``spl.dsl.tsm.language``) reads these exactly as it reads textX's
objects. :class:`TsmTokens` adds the .tsm's names and strings to the shared
:class:`~spl.dsl.parse_tree.Tokens`; the regular expressions are the grammar's own.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

from spl.dsl.parse_tree import Refused as Refused, Tokens, rule
from spl.dsl.tsm.options import INTERFACE_OPTIONS
from spl.metamodels.interface_kinds import KINDS, InterfaceKind

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


# The rules, one class each: its fields as the grammar gives them (``position`` first, the
# offset of the first token). The type checker reads each as a NamedTuple; at run time
# parse_tree.Rule makes the class from the same declaration. textX's objects of a rule
# have the same attributes.
if TYPE_CHECKING:
    from typing import NamedTuple as Rule
else:
    from spl.dsl.parse_tree import Rule


class Str(Rule):
    position: int
    value: str  # the quoted text, quotes and escapes as written


class Int(Rule):
    position: int
    value: str


class Name(Rule):
    position: int
    name: str


class Ref(Rule):
    position: int
    name: str


class QRef(Rule):
    position: int
    parts: list[Name]


class TypeRef(Rule):
    position: int
    value: str


class ImplRef(Rule):
    position: int
    value: str


class EnvPassword(Rule):
    position: int
    variable: Str


class LiteralPassword(Rule):
    position: int
    literal: Str


class Endpoint(Rule):
    position: int
    robotId: Str | None
    url: Str | None
    user: Str | None
    password: EnvPassword | LiteralPassword | None


class StringValue(Rule):
    position: int
    value: Str


class BoolValue(Rule):
    position: int
    value: str


class NumberValue(Rule):
    position: int
    value: str


class Parameter(Rule):
    position: int
    name: Name
    type: str
    value: StringValue | BoolValue | NumberValue | None


# A node's interface statements: one rule per kind of the registry (docs/architecture.md,
# "Interface kinds"), so a new kind needs no class here. The type checker reads the four
# shapes below; at run time each kind's rule is made with its shape's fields.
if TYPE_CHECKING:

    class Publishes(Rule):  # a topic's providing side
        position: int
        name: Name
        type: TypeRef | None
        topic: Ref | None

    class Subscribes(Rule):  # a topic's input
        position: int
        name: Name
        type: TypeRef | None
        topic: Ref | None
        external: Str | None

    class Provides(Rule):  # a server, of any family called
        position: int
        name: Name
        type: TypeRef
        rosName: Str | None

    class Calls(Rule):  # a caller of one server
        position: int
        name: Name
        type: TypeRef | None
        server: QRef | None
        external: Str | None

    NodeInterface = Publishes | Subscribes | Provides | Calls
    NodeMember = Parameter | NodeInterface


def _interface_rule(kind: InterfaceKind) -> Any:
    """A server binds nothing, any other kind its ``binds``; then the grammar's options."""
    fields = ["name", "type"] if kind.binds is None else ["name", "type", kind.binds]
    fields += [option.attribute for option in INTERFACE_OPTIONS[kind.rule]]
    made = rule(kind.rule, " ".join(fields))
    made.__module__ = __name__
    return made


# the class of each interface statement's rule, by the rule's name in tsm.tx
INTERFACE_RULES: dict[str, Any] = {kind.rule: _interface_rule(kind) for kind in KINDS}


class Topic(Rule):
    position: int
    name: Name
    type: TypeRef
    rosName: Str | None


class Node(Rule):
    position: int
    optional: bool
    name: Name
    sharing: str | None
    implementation: ImplRef | None
    args: Str | None
    members: list[NodeMember]


class Period(Rule):
    position: int
    value: str


class Refinement(Rule):
    position: int
    output: Ref
    transform: Ref
    period: Period


class Store(Rule):
    position: int
    optional: bool
    name: Name
    raw: Ref
    refinements: list[Refinement]


class Writer(Rule):
    position: int
    optional: bool
    name: Name
    dataType: Ref
    store: QRef
    topic: Ref
    implementation: ImplRef | None
    args: Str | None
    parameters: list[Parameter]


class Reader(Rule):
    position: int
    optional: bool
    name: Name
    dataType: Ref
    store: QRef
    topic: Ref
    subscribe: bool
    period: Period
    implementation: ImplRef | None
    args: Str | None
    parameters: list[Parameter]


if TYPE_CHECKING:
    Member = Topic | Node | Writer | Reader | Store


class RobotContainer(Rule):
    position: int
    name: Name
    endpoint: Endpoint | None
    namespace: Str | None
    members: list[Member]


class CloudContainer(Rule):
    position: int
    name: Name
    group: Str | None
    size: Int | None
    cpu: Int | None
    memory: Int | None
    bandwidth: Int | None
    namespace: Str | None
    members: list[Member]


class Bridge(Rule):
    position: int
    source: QRef
    target: QRef


class Field(Rule):
    position: int
    name: Name
    type: str


class DataType(Rule):
    position: int
    name: Name
    fields: list[Field]


# the expressions of transforms
class OrExpr(Rule):
    position: int
    operands: list[AndExpr]


class AndExpr(Rule):
    position: int
    operands: list[NotOp | Comparison]


class NotOp(Rule):
    position: int
    operand: NotOp | Comparison


class Comparison(Rule):
    position: int
    left: Additive
    operator: str | None
    right: Additive | None


class Additive(Rule):
    position: int
    operands: list[Multiplicative]
    operators: list[str]


class Multiplicative(Rule):
    position: int
    operands: list[Negation | Postfix]
    operators: list[str]


class Negation(Rule):
    position: int
    operand: Negation | Postfix


class Index(Rule):
    position: int
    index: OrExpr  # type: ignore[assignment]  # the grammar's name (shadows tuple.index)


class Postfix(Rule):
    position: int
    primary: Primary
    indexes: list[Index]


class Parenthesized(Rule):
    position: int
    inner: OrExpr


class NumberLiteral(Rule):
    position: int
    value: str


class BooleanLiteral(Rule):
    position: int
    value: str


class StringLiteral(Rule):
    position: int
    value: Str


class Call(Rule):
    position: int
    function: Name
    arguments: list[OrExpr]


class Reference(Rule):
    position: int
    parts: list[Name]


if TYPE_CHECKING:
    Primary = NumberLiteral | BooleanLiteral | StringLiteral | Call | Reference | Parenthesized


class Assignment(Rule):
    position: int
    field: Name
    expression: OrExpr


class Transform(Rule):
    position: int
    name: Name
    input: Ref
    output: Ref
    assignments: list[Assignment]


class System(Rule):
    position: int
    name: Name | None
    elements: list[DataType | Transform | RobotContainer | CloudContainer | Bridge]


class TsmTokens(Tokens):
    """The shared cursor with the .tsm's names, qualified references and strings.

    Every method that reads commits: where the text holds something else it raises
    :class:`Refused` (no backtracking, see ``spl.dsl.tsm.reader``)."""

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
