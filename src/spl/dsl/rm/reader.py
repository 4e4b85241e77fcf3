"""A fast reader of ``rm.tx``: the parse tree textX makes, without building its metamodel.

Building textX's metamodel of rm.tx took a tenth of a second of every ``spl check``.
This reader follows the grammar rule by rule, a PEG as textX's is: the statements are
an ordered choice tried in the grammar's order with backtracking, because rm.tx is not
built with ``autokwd`` and a keyword may run into the name after it (``connect
bridgeA.b to topic T`` is a ConnectTopicStmt whose interface is ``bridgeA.b``).
Keywords are therefore matched as written, names as ``Ident ('.' Ident)*`` joined into
one string, ``STRING`` with textX's own expression and unescaping. The objects carry
the class names, attributes and ``_tx_position`` textX gives, so the builder
(``spl.dsl.rm.language``) cannot tell them apart.

It never reports a problem: on anything it does not read to the end it returns None
and textX parses the text and words the syntax error (``tests/test_rm_reader.py``
compares both trees).

It pays (``bench/readers.py``, docs/performance.md "Fast readers", CPU time on a loaded
2-core machine): ``spl check`` of the shipped mapping3d line takes 0.27 s of CPU with it
and 0.33 s without (textX's import and metamodel of rm.tx, 0.045 s and 0.013 s, and a
tree 12x faster to make); the .rm of the 10,000-node synthetic line of
``bench/tsm_scale.py`` is read in 0.057 s instead of 0.80 s (14x).

A keyword added to ``rm.tx`` must be read here too:
``tests/test_grammar_keywords.py`` fails on one the reader never matches.
"""

from __future__ import annotations

import re
from typing import Any

from spl.dsl.parse_tree import Refused, Tokens, rule

# The terminals of rm.tx as textX compiles them (re.MULTILINE is arpeggio's default);
# STRING is textX's built-in rule.
IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?![^\x00-\x7f])", re.MULTILINE)
ROS_TYPE = re.compile(r"[A-Za-z][A-Za-z0-9_]*\/[A-Za-z0-9_][A-Za-z0-9_.\-]*", re.MULTILINE)
NUMBER = re.compile(
    r"[-+]?(\d+\.\d*([eE][-+]?\d+)?|\.\d+([eE][-+]?\d+)?|\d+[eE][-+]?\d+|\d+)(?![\w.])",
    re.MULTILINE,
)
STRING = re.compile(r'("(\\"|[^"])*")|(\'(\\\'|[^\'])*\')', re.MULTILINE)

ResolutionModel = rule("ResolutionModel", "name tsm fm elements")
Element = rule("Element", "feature negated statements")
Require = rule("Require", "refs")
ImplementationStmt = rule("ImplementationStmt", "node implementation args")
ConnectTopicStmt = rule("ConnectTopicStmt", "interface topic")
ConnectNewTopicStmt = rule("ConnectNewTopicStmt", "interface name type rosName")
ConnectServerStmt = rule("ConnectServerStmt", "client server")
ConnectBridgeStmt = rule("ConnectBridgeStmt", "source target")
ParameterStmt = rule("ParameterStmt", "parameter value")
FeatureAttributeValue = rule("FeatureAttributeValue", "feature attribute")
StringValue = rule("StringValue", "value")
BoolValue = rule("BoolValue", "value")
NumberValue = rule("NumberValue", "value")
MigrateStmt = rule("MigrateStmt", "node container")


def read(text: str) -> Any:
    """The textX parse tree of ``text`` (a ``ResolutionModel``), or None to leave it to
    textX."""
    reader = _Reader(text)
    try:
        tree = reader.resolution_model()
    except Refused:
        return None
    return tree if reader.at_end() else None


class _Reader(Tokens):
    """The rules of rm.tx, one method each."""

    def resolution_model(self) -> Any:
        start = self.punct("resolution")
        self.punct("model")
        name = self.ident()
        self.punct("tsm")
        tsm = self.string()
        self.punct("fm")
        fm = self.string()
        return ResolutionModel(start, name, tsm, fm, self.repeated(self.element))

    def element(self) -> Any:
        """``'when' feature=Ident (negated?='not')? 'selected' '{' statements*=Statement '}'``"""
        start = self.punct("when")
        feature = self.ident()
        negated = self.at("not")
        if negated:
            self.punct("not")
        self.punct("selected")
        self.punct("{")
        statements = self.repeated(self.statement)
        self.punct("}")
        return Element(start, feature, negated, statements)

    def statement(self) -> Any:
        return self.first(
            self.require,
            self.implementation,
            self.connect_bridge,
            self.connect_new_topic,
            self.connect_topic,
            self.connect_server,
            self.parameter,
            self.migrate,
        )

    # -- terminals -------------------------------------------------------------------
    def ident(self) -> str:
        return self.match(IDENT)[1]

    def qname(self) -> str:
        """QName: ``Ident ('.' Ident)*``, a match rule: its parts joined."""
        parts = [self.ident(), *self.repeated(self.dotted)]
        return "".join(parts)

    def dotted(self) -> str:
        self.punct(".")
        return "." + self.ident()

    def string(self) -> str:
        """textX's STRING: the text between the quotes, escaped quotes unescaped."""
        quoted = self.match(STRING)[1]
        return quoted[1:-1].replace(r"\"", '"').replace(r"\'", "'")

    # -- statements --------------------------------------------------------------------
    def require(self) -> Any:
        start = self.punct("require")
        refs = [self.qname(), *self.repeated(self.comma_qname)]
        return Require(start, refs)

    def comma_qname(self) -> str:
        self.punct(",")
        return self.qname()

    def implementation(self) -> Any:
        start = self.punct("implementation")
        node = self.qname()
        self.punct("=")
        implementation = self.match(ROS_TYPE)[1]
        return ImplementationStmt(start, node, implementation, self.optional(self.args))

    def args(self) -> Any:
        self.punct("args")
        return self.string_value()

    def connect_topic(self) -> Any:
        start = self.punct("connect")
        interface = self.qname()
        self.punct("to")
        self.punct("topic")
        return ConnectTopicStmt(start, interface, self.qname())

    def connect_new_topic(self) -> Any:
        start = self.punct("connect")
        interface = self.qname()
        self.punct("to")
        self.punct("new")
        self.punct("topic")
        name = self.ident()
        self.punct(":")
        kind = self.match(ROS_TYPE)[1]
        ros_name = self.optional(self.ros_name, "")
        return ConnectNewTopicStmt(start, interface, name, kind, ros_name)

    def ros_name(self) -> str:
        self.punct("name")
        return self.string()

    def connect_server(self) -> Any:
        start = self.punct("connect")
        client = self.qname()
        self.punct("to")
        self.punct("server")
        return ConnectServerStmt(start, client, self.qname())

    def connect_bridge(self) -> Any:
        start = self.punct("connect")
        self.punct("bridge")
        source = self.qname()
        self.punct("->")
        return ConnectBridgeStmt(start, source, self.qname())

    def parameter(self) -> Any:
        start = self.punct("parameter")
        parameter = self.qname()
        self.punct("=")
        value = self.first(
            self.feature_attribute, self.string_value, self.bool_value, self.number_value
        )
        return ParameterStmt(start, parameter, value)

    def feature_attribute(self) -> Any:
        start = self.punct("feature")
        feature = self.ident()
        self.punct(".")
        return FeatureAttributeValue(start, feature, self.ident())

    def string_value(self) -> Any:
        return StringValue(self.skip(), self.string())

    def bool_value(self) -> Any:
        at = self.skip()
        for word in ("true", "false"):
            if self.text.startswith(word, at):
                self.pos = at + len(word)
                return BoolValue(at, word)
        raise Refused

    def number_value(self) -> Any:
        return NumberValue(*self.match(NUMBER))

    def migrate(self) -> Any:
        start = self.punct("migrate")
        node = self.qname()
        self.punct("to")
        return MigrateStmt(start, node, self.ident())
