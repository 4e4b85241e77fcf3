"""The parse tree of ``tsm.tx`` as textX shapes it, and the terminals it is read from.

One class per grammar rule, named after it, holding the rule's attributes (``None``,
``False`` or ``[]`` where textX leaves them unset) and ``_tx_position``, the offset of
its first token: the builder (``spl.dsl.tsm``) reads these exactly as it reads textX's
objects. :class:`TsmTokens` adds the .tsm's names and strings to the shared
:class:`~spl.dsl.parse_tree.Tokens`; the regular expressions are the grammar's own.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any, NamedTuple

from spl.dsl.parse_tree import Refused as Refused
from spl.dsl.parse_tree import Tokens
from spl.dsl.parse_tree import rule as _rule

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


if TYPE_CHECKING:
    # The rules for the type checker: one NamedTuple per rule, its fields as the grammar
    # gives them (``position`` first, the offset of the first token). At run time the
    # classes are made by parse_tree.rule (below); tests/test_ecore_types.py checks that
    # both name the same fields. textX's objects of a rule have the same attributes.

    class Str(NamedTuple):
        position: int
        value: str  # the quoted text, quotes and escapes as written

    class Int(NamedTuple):
        position: int
        value: str

    class Name(NamedTuple):
        position: int
        name: str

    class Ref(NamedTuple):
        position: int
        name: str

    class QRef(NamedTuple):
        position: int
        parts: list[Name]

    class TypeRef(NamedTuple):
        position: int
        value: str

    class ImplRef(NamedTuple):
        position: int
        value: str

    class EnvPassword(NamedTuple):
        position: int
        variable: Str

    class LiteralPassword(NamedTuple):
        position: int
        literal: Str

    class Endpoint(NamedTuple):
        position: int
        robotId: Str | None
        url: Str | None
        user: Str | None
        password: EnvPassword | LiteralPassword | None

    class StringValue(NamedTuple):
        position: int
        value: Str

    class BoolValue(NamedTuple):
        position: int
        value: str

    class NumberValue(NamedTuple):
        position: int
        value: str

    class Parameter(NamedTuple):
        position: int
        name: Name
        type: str
        value: StringValue | BoolValue | NumberValue | None

    class Publishes(NamedTuple):
        position: int
        name: Name
        type: TypeRef | None
        topic: Ref | None

    class Subscribes(NamedTuple):
        position: int
        name: Name
        type: TypeRef | None
        topic: Ref | None
        external: Str | None

    class Provides(NamedTuple):
        position: int
        name: Name
        type: TypeRef
        rosName: Str | None

    class Calls(NamedTuple):
        position: int
        name: Name
        type: TypeRef | None
        server: QRef | None
        external: Str | None

    NodeMember = Parameter | Publishes | Subscribes | Provides | Calls

    class Topic(NamedTuple):
        position: int
        name: Name
        type: TypeRef
        rosName: Str | None

    class Node(NamedTuple):
        position: int
        optional: bool
        name: Name
        sharing: str | None
        implementation: ImplRef | None
        args: Str | None
        members: list[NodeMember]

    class Period(NamedTuple):
        position: int
        value: str

    class Refinement(NamedTuple):
        position: int
        output: Ref
        transform: Ref
        period: Period

    class Store(NamedTuple):
        position: int
        optional: bool
        name: Name
        raw: Ref
        refinements: list[Refinement]

    class Writer(NamedTuple):
        position: int
        optional: bool
        name: Name
        dataType: Ref
        store: QRef
        topic: Ref
        implementation: ImplRef | None
        args: Str | None
        parameters: list[Parameter]

    class Reader(NamedTuple):
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

    Member = Topic | Node | Writer | Reader | Store

    class RobotContainer(NamedTuple):
        position: int
        name: Name
        endpoint: Endpoint | None
        namespace: Str | None
        members: list[Member]

    class CloudContainer(NamedTuple):
        position: int
        name: Name
        group: Str | None
        size: Int | None
        cpu: Int | None
        memory: Int | None
        bandwidth: Int | None
        namespace: Str | None
        members: list[Member]

    class Bridge(NamedTuple):
        position: int
        source: QRef
        target: QRef

    class Field(NamedTuple):
        position: int
        name: Name
        type: str

    class DataType(NamedTuple):
        position: int
        name: Name
        fields: list[Field]

    # the expressions of transforms
    class OrExpr(NamedTuple):
        position: int
        operands: list[AndExpr]

    class AndExpr(NamedTuple):
        position: int
        operands: list[NotOp | Comparison]

    class NotOp(NamedTuple):
        position: int
        operand: NotOp | Comparison

    class Comparison(NamedTuple):
        position: int
        left: Additive
        operator: str | None
        right: Additive | None

    class Additive(NamedTuple):
        position: int
        operands: list[Multiplicative]
        operators: list[str]

    class Multiplicative(NamedTuple):
        position: int
        operands: list[Negation | Postfix]
        operators: list[str]

    class Negation(NamedTuple):
        position: int
        operand: Negation | Postfix

    class Index(NamedTuple):
        position: int
        index: OrExpr  # type: ignore[assignment]  # the grammar's name (shadows tuple.index)

    class Postfix(NamedTuple):
        position: int
        primary: Primary
        indexes: list[Index]

    class Parenthesized(NamedTuple):
        position: int
        inner: OrExpr

    class NumberLiteral(NamedTuple):
        position: int
        value: str

    class BooleanLiteral(NamedTuple):
        position: int
        value: str

    class StringLiteral(NamedTuple):
        position: int
        value: Str

    class Call(NamedTuple):
        position: int
        function: Name
        arguments: list[OrExpr]

    class Reference(NamedTuple):
        position: int
        parts: list[Name]

    Primary = NumberLiteral | BooleanLiteral | StringLiteral | Call | Reference | Parenthesized

    class Assignment(NamedTuple):
        position: int
        field: Name
        expression: OrExpr

    class Transform(NamedTuple):
        position: int
        name: Name
        input: Ref
        output: Ref
        assignments: list[Assignment]

    class System(NamedTuple):
        position: int
        name: Name | None
        elements: list[DataType | Transform | RobotContainer | CloudContainer | Bridge]

else:
    System = _rule("System", "name elements")
    RobotContainer = _rule("RobotContainer", "name endpoint namespace members")
    CloudContainer = _rule(
        "CloudContainer", "name group size cpu memory bandwidth namespace members"
    )
    Endpoint = _rule("Endpoint", "robotId url user password")
    EnvPassword = _rule("EnvPassword", "variable")
    LiteralPassword = _rule("LiteralPassword", "literal")
    Topic = _rule("Topic", "name type rosName")
    Node = _rule("Node", "optional name sharing implementation args members")
    Parameter = _rule("Parameter", "name type value")
    StringValue = _rule("StringValue", "value")
    BoolValue = _rule("BoolValue", "value")
    NumberValue = _rule("NumberValue", "value")
    Publishes = _rule("Publishes", "name type topic")
    Subscribes = _rule("Subscribes", "name type topic external")
    Provides = _rule("Provides", "name type rosName")
    Calls = _rule("Calls", "name type server external")
    Bridge = _rule("Bridge", "source target")
    DataType = _rule("DataType", "name fields")
    Field = _rule("Field", "name type")
    Transform = _rule("Transform", "name input output assignments")
    Assignment = _rule("Assignment", "field expression")
    Store = _rule("Store", "optional name raw refinements")
    Refinement = _rule("Refinement", "output transform period")
    Period = _rule("Period", "value")
    Writer = _rule("Writer", "optional name dataType store topic implementation args parameters")
    Reader = _rule(
        "Reader",
        "optional name dataType store topic subscribe period implementation args parameters",
    )
    OrExpr = _rule("OrExpr", "operands")
    AndExpr = _rule("AndExpr", "operands")
    NotOp = _rule("NotOp", "operand")
    Comparison = _rule("Comparison", "left operator right")
    Additive = _rule("Additive", "operands operators")
    Multiplicative = _rule("Multiplicative", "operands operators")
    Negation = _rule("Negation", "operand")
    Postfix = _rule("Postfix", "primary indexes")
    Index = _rule("Index", "index")
    Parenthesized = _rule("Parenthesized", "inner")
    NumberLiteral = _rule("NumberLiteral", "value")
    BooleanLiteral = _rule("BooleanLiteral", "value")
    StringLiteral = _rule("StringLiteral", "value")
    Call = _rule("Call", "function arguments")
    Reference = _rule("Reference", "parts")
    Name = _rule("Name", "name")
    Ref = _rule("Ref", "name")
    QRef = _rule("QRef", "parts")
    TypeRef = _rule("TypeRef", "value")
    ImplRef = _rule("ImplRef", "value")
    Str = _rule("Str", "value")
    Int = _rule("Int", "value")


class TsmTokens(Tokens):
    """The shared cursor with the .tsm's names, qualified references and strings.

    Every method that reads commits: where the text holds something else it raises
    :class:`Refused` (no backtracking, see ``spl.dsl.tsm_reader``)."""

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
