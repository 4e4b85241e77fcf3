"""The Template System Model language (.tsm): parse, resolve names, check, build pyecore.

The textX grammar (``tsm.tx``) only shapes the text; everything that needs a reason
(ROS naming rules, references, types, credentials, transform expressions) is checked
here so every problem is reported at once, at the column of the offending name, as
``file:line:col: error: message``. The result is a ``tsm.System`` of
``metamodels/tsm.ecore``; nothing in a model is ever evaluated.

A bridge is not an element of its own: exactly as in the Rapyuta metamodel it becomes
one endpoint interface in each container plus an ``EndpointConnection``. The endpoint
interfaces get canonical names (the ``endpoint_*_name`` functions) which the resolver's
node migration uses too, so the printer can write every connection back as a bridge.
"""

from __future__ import annotations

import bisect
import math
import re
from collections.abc import Callable
from functools import cache
from importlib.resources import files
from pathlib import Path
from typing import Any

from textx import TextXSyntaxError, metamodel_from_file

from spl.diagnostics import (
    Diagnostic,
    DiagnosticSink,
    Location,
    ModelError,
    counted,
    model_text,
)
from spl.dsl import literals, rosnames, transform_types
from spl.metamodels import tsm as tsm_metamodel

__all__ = [
    "FUNCTIONS",
    "RESERVED_FIELD_NAMES",
    "endpoint_client_name",
    "endpoint_publisher_name",
    "endpoint_server_name",
    "endpoint_subscriber_name",
    "normalize_endpoints",
    "parse_file",
    "parse_text",
    "summary",
]

# Functions a transform may call, with (fewest, most) arguments; `if(c, a, b)` is the
# conditional. Nothing else can be called, so generated code can map each one safely
# (the same table as generators/expressions.py).
FUNCTIONS: dict[str, tuple[int, int]] = {
    "abs": (1, 1),
    "min": (2, 16),
    "max": (2, 16),
    "sqrt": (1, 1),
    "exp": (1, 1),
    "log": (1, 1),
    "sin": (1, 1),
    "cos": (1, 1),
    "tan": (1, 1),
    "asin": (1, 1),
    "acos": (1, 1),
    "atan": (1, 1),
    "atan2": (2, 2),
    "floor": (1, 1),
    "ceil": (1, 1),
    "round": (1, 1),
    "if": (3, 3),
}
CONSTANTS = {"pi": math.pi, "e": math.e}
NEIGHBOURS = ("prev", "next")
IMPLICIT_FIELD = "timestamp"
# Words an expression reads specially; a data field may not be called so.
RESERVED_FIELD_NAMES = frozenset(
    {"and", "or", "not", "true", "false", "if", IMPLICIT_FIELD, *NEIGHBOURS, *CONSTANTS}
)


# -- canonical endpoint interface names (shared with the resolver) ---------------------
def endpoint_subscriber_name(topic: Any) -> str:
    """The endpoint Subscriber sending ``topic`` out of its container."""
    return f"sub_{topic.name}"


def endpoint_publisher_name(topic: Any) -> str:
    """The endpoint Publisher publishing bridged data on ``topic``."""
    return f"pub_{topic.name}"


def endpoint_server_name(server: Any) -> str:
    """The endpoint ServiceServer standing in for node server ``server`` elsewhere."""
    return f"srv_{server.eContainer().name}_{server.name}"


def endpoint_client_name(server: Any) -> str:
    """The endpoint ServiceClient calling node server ``server`` in its container."""
    return f"cli_{server.eContainer().name}_{server.name}"


# -- public entry points ------------------------------------------------------------------
@cache
def _grammar() -> Any:
    return metamodel_from_file(
        str(files(__package__).joinpath("tsm.tx")), autokwd=True, use_regexp_group=False
    )


def parse_file(path: str | Path) -> Any:
    """Parse and check a .tsm file; raise ModelError with every problem found."""
    return parse_text(model_text(path), str(path))


def parse_text(text: str, filename: str = "<string>") -> Any:
    """Parse and check .tsm text; ``filename`` is what diagnostics name."""
    sink = DiagnosticSink()
    try:
        tree = _grammar().model_from_str(text, file_name=filename)
        if isinstance(tree, str):  # textX gives '' for text holding no element at all
            return tsm_metamodel().System(srcFile=filename, srcLine=1, srcCol=1)
        system = _Builder(text, filename, sink).build(tree)
        sink.raise_if_errors()
        # types of transform expressions, once every name is known to resolve
        sink.diagnostics.extend(transform_types.check_system(system))
    except TextXSyntaxError as exc:
        raise ModelError([_syntax_diagnostic(exc, text, filename)]) from None
    except RecursionError:  # only transform expressions nest; a hostile file nests deep
        message = "a transform expression is nested too deeply or too long"
        raise ModelError([Diagnostic(Location(filename, 1, 1), message)]) from None
    sink.raise_if_errors()
    return system


def summary(system: Any) -> str:
    """One line of counts for ``spl check``."""
    nodes = [n for c in system.containers for n in c.nodes]
    parts = [
        counted(len(system.containers), "container"),
        counted(len(nodes), "node"),
        counted(sum(len(c.topics) for c in system.containers), "topic"),
        counted(sum(len(n.interfaces) for n in nodes), "interface"),
        counted(len(system.connections), "bridge"),
    ]
    stores = sum(len(c.stores) for c in system.containers)
    if system.dataTypes or system.transforms or stores:
        parts += [
            counted(len(system.dataTypes), "data type"),
            counted(len(system.transforms), "transform"),
            counted(stores, "store"),
        ]
    return ", ".join(parts)


def normalize_endpoints(system: Any) -> None:
    """Order endpoint interfaces the way parsing the printed model creates them.

    The printer writes connections as bridges in ``System.connections`` order and the
    parser creates endpoint interfaces in bridge order; a transformation that adds or
    removes endpoint interfaces calls this so that print/parse round trips stay exact.
    """
    order: dict[int, int] = {}

    def see(interface: Any) -> None:
        order.setdefault(id(interface), len(order))

    for connection in system.connections:
        source, target = connection.source, connection.target
        if source.eClass.name == "ServiceServer":
            if any(True for _ in _bridged_clients(source)):
                see(source)
                see(target)
        else:
            see(source)
            see(target)
    for container in system.containers:
        interfaces = list(container.endpoint.interfaces) if container.endpoint else []
        ranked = sorted(enumerate(interfaces), key=lambda p: order.get(id(p[1]), len(order) + p[0]))
        if [i for _, i in ranked] != interfaces:
            container.endpoint.interfaces.clear()
            container.endpoint.interfaces.extend(i for _, i in ranked)


def _bridged_clients(stand_in: Any):
    """Node service clients bound to the endpoint server ``stand_in``, in model order."""
    container = stand_in.eContainer().eContainer()
    for node in container.nodes:
        for interface in node.interfaces:
            if interface.eClass.name == "ServiceClient" and interface.server is stand_in:
                yield node, interface


# -- syntax errors ----------------------------------------------------------------------
_RULE_WORDS = {
    "Ident": "a name",
    "RosType": "a type package/Type",
    "QuotedString": 'a string "..."',
    "UnsignedNumber": "a number",
    "SignedNumber": "a number",
    "Boolean": "true or false",
}


def _syntax_diagnostic(exc: TextXSyntaxError, text: str, filename: str) -> Diagnostic:
    line, col = exc.line or 1, exc.col or 1
    offset = _offset(text, line, col)
    token = re.match(r"\S{0,30}", text[offset:]).group(0) if offset < len(text) else ""
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


def _decode(quoted: str) -> str:
    """The content of a grammar string: the grammar allows only \\" \\\\ \\n \\t escapes."""
    escapes = {'"': '"', "\\": "\\", "n": "\n", "t": "\t"}
    return re.sub(r"\\(.)", lambda m: escapes[m.group(1)], quoted[1:-1])


def _kind(tree: Any) -> str:
    return type(tree).__name__


# -- the builder --------------------------------------------------------------------------
class _Builder:
    """Turns the textX tree into a tsm.System, resolving names and collecting problems."""

    def __init__(self, text: str, filename: str, sink: DiagnosticSink) -> None:
        self.filename = filename
        self.sink = sink
        self.T = tsm_metamodel()
        self._line_starts = [0] + [m.end() for m in re.finditer("\n", text)]
        self.system: Any = None
        self.containers: dict[str, Any] = {}
        self.data_types: dict[str, Any] = {}
        self.transforms: dict[str, Any] = {}
        # model element -> its parse tree, for the resolution passes
        self.trees: list[tuple[Any, Any]] = []

    # -- locations ---------------------------------------------------------------------
    def loc(self, tree: Any) -> Location:
        pos = tree._tx_position
        index = bisect.bisect_right(self._line_starts, pos) - 1
        return Location(self.filename, index + 1, pos - self._line_starts[index] + 1)

    def locate(self, element: Any, tree: Any) -> Any:
        where = self.loc(tree)
        element.srcFile, element.srcLine, element.srcCol = where.file, where.line, where.col
        return element

    def error(self, tree: Any, message: str) -> None:
        self.sink.error(self.loc(tree), message)

    def check(self, tree: Any, problem: str | None) -> bool:
        if problem:
            self.error(tree, problem)
        return problem is None

    def declare(
        self, scope: dict[str, Any], element: Any, name_tree: Any, what: str, where: str = ""
    ) -> None:
        """Register ``element`` under its name in ``scope``; report a duplicate."""
        first = scope.get(element.name)
        if first is not None:
            self.error(
                name_tree,
                f"duplicate {what} name {element.name}{where} "
                f"(first declared at line {first.srcLine})",
            )
        else:
            scope[element.name] = element

    # -- passes ------------------------------------------------------------------------
    def build(self, tree: Any) -> Any:
        T = self.T
        self.system = system = T.System()
        if tree.name is not None:
            system.name = tree.name.name
            self.locate(system, tree.name)
        else:
            self.locate(system, tree)
        bridges = []
        for element in tree.elements:
            kind = _kind(element)
            if kind == "DataType":
                system.dataTypes.append(self._data_type(element))
            elif kind == "Transform":
                system.transforms.append(self._transform_declaration(element))
            elif kind in ("RobotContainer", "CloudContainer"):
                system.containers.append(self._container(element))
            else:
                bridges.append(element)
        for element, element_tree in self.trees:
            getattr(self, f"_resolve_{element_tree.__class__.__name__}")(element, element_tree)
        for bridge in bridges:
            self._bridge(bridge)
        return system

    # -- data types and transforms ------------------------------------------------------
    def _data_type(self, tree: Any) -> Any:
        data_type = self.locate(self.T.DataType(name=tree.name.name), tree.name)
        self.declare(self.data_types, data_type, tree.name, "data type")
        fields: dict[str, Any] = {}
        for field_tree in tree.fields:
            name = field_tree.name.name
            field = self.locate(
                self.T.Field(name=name, type=self.T.FieldType.getEEnumLiteral(field_tree.type)),
                field_tree.name,
            )
            if name in RESERVED_FIELD_NAMES:
                self.error(
                    field_tree.name,
                    f"field name {name} is reserved in transform expressions"
                    + (" (every record has a timestamp)" if name == IMPLICIT_FIELD else ""),
                )
            self.declare(fields, field, field_tree.name, "field", f" in data {data_type.name}")
            data_type.fields.append(field)
        return data_type

    def _transform_declaration(self, tree: Any) -> Any:
        transform = self.locate(self.T.Transform(name=tree.name.name), tree.name)
        self.declare(self.transforms, transform, tree.name, "transform")
        self.trees.append((transform, tree))
        return transform

    def _data_type_ref(self, ref: Any) -> Any:
        found = self.data_types.get(ref.name)
        if found is None:
            self.error(ref, f"unknown data type {ref.name}")
        return found

    def _resolve_Transform(self, transform: Any, tree: Any) -> None:
        source = self._data_type_ref(tree.input)
        target = self._data_type_ref(tree.output)
        transform.input, transform.output = source, target
        assigned: dict[str, Any] = {}
        outputs = {f.name for f in target.fields} if target is not None else None
        for assignment_tree in tree.assignments:
            name = assignment_tree.field.name
            assignment = self.locate(self.T.Assignment(field=name), assignment_tree.field)
            if outputs is not None and name not in outputs:
                reason = (
                    "the timestamp is kept from the input record"
                    if name == IMPLICIT_FIELD
                    else f"fields: {', '.join(sorted(outputs)) or 'none'}"
                )
                self.error(
                    assignment_tree.field,
                    f"unknown field {name} of output type {target.name} ({reason})",
                )
            elif name in assigned:
                self.error(
                    assignment_tree.field,
                    f"field {name} is assigned twice (first at line {assigned[name].srcLine})",
                )
            else:
                assigned[name] = assignment
            expression = self._expression(assignment_tree.expression, source)
            if expression is not None:
                assignment.expression = expression
            transform.assignments.append(assignment)
        if outputs is not None:
            missing = [f.name for f in target.fields if f.name not in assigned]
            if missing:
                self.error(
                    tree.name,
                    f"transform {transform.name} does not assign field(s) "
                    f"{', '.join(missing)} of {target.name}",
                )

    # -- expressions --------------------------------------------------------------------
    def _expression(self, tree: Any, record_type: Any) -> Any:
        """The Expression model of ``tree``; None (with errors reported) when refused."""
        T = self.T
        kind = _kind(tree)
        if kind in ("OrExpr", "AndExpr"):
            operator = "or" if kind == "OrExpr" else "and"
            return self._fold(
                tree, tree.operands, [operator] * (len(tree.operands) - 1), record_type
            )
        if kind in ("Additive", "Multiplicative"):
            return self._fold(tree, tree.operands, tree.operators, record_type)
        if kind == "NotOp":
            operand = self._expression(tree.operand, record_type)
            if operand is None:
                return None
            return self.locate(T.UnaryExpression(operator="not", operand=operand), tree)
        if kind == "Negation":
            operand = self._expression(tree.operand, record_type)
            if operand is None:
                return None
            return self.locate(T.UnaryExpression(operator="-", operand=operand), tree)
        if kind == "Comparison":
            left = self._expression(tree.left, record_type)
            if tree.operator is None or tree.operator == "":
                return left
            right = self._expression(tree.right, record_type)
            if left is None or right is None:
                return None
            return self.locate(
                T.BinaryExpression(operator=tree.operator, left=left, right=right), tree
            )
        if kind == "Postfix":
            if tree.indexes:
                self.error(tree.indexes[0], "indexing is not allowed in transform expressions")
                return None
            return self._expression(tree.primary, record_type)
        if kind == "Parenthesized":
            return self._expression(tree.inner, record_type)
        if kind == "NumberLiteral":
            return self._number(tree, tree.value)
        if kind == "BooleanLiteral":
            return self.locate(T.BooleanLiteral(value=tree.value == "true"), tree)
        if kind == "StringLiteral":
            self.error(tree, "strings are not allowed in transform expressions")
            return None
        if kind == "Call":
            return self._call(tree, record_type)
        if kind == "Reference":
            return self._reference(tree, record_type)
        raise AssertionError(f"unhandled expression rule {kind}")  # grammar and builder disagree

    def _fold(self, tree: Any, operand_trees: list, operators: list, record_type: Any) -> Any:
        operands = [self._expression(o, record_type) for o in operand_trees]
        if any(o is None for o in operands):
            return None
        result = operands[0]
        for operator, operand in zip(operators, operands[1:], strict=True):
            binary = self.T.BinaryExpression(operator=operator, left=result, right=operand)
            result = self.locate(binary, operand_trees[0])
        return result

    def _number(self, tree: Any, text: str) -> Any:
        if re.fullmatch(r"\d+", text):
            value = literals.int_literal(text)
            if value is None:
                self.error(tree, f"number {text} is out of range")
                return None
            canonical = str(value)
        else:
            value = float(text)
            if not math.isfinite(value):
                self.error(tree, f"number {text} is out of range")
                return None
            canonical = repr(value)
        return self.locate(self.T.NumberLiteral(value=canonical), tree)

    def _call(self, tree: Any, record_type: Any) -> Any:
        name = tree.function.name
        arity = FUNCTIONS.get(name)
        if arity is None:
            self.error(
                tree.function,
                f"unknown function {name} (allowed: {', '.join(sorted(FUNCTIONS))})",
            )
            return None
        fewest, most = arity
        count = len(tree.arguments)
        if not fewest <= count <= most:
            wanted = str(fewest) if fewest == most else f"{fewest} to {most}"
            self.error(tree.function, f"function {name} takes {wanted} arguments, got {count}")
            return None
        arguments = [self._expression(a, record_type) for a in tree.arguments]
        if any(a is None for a in arguments):
            return None
        call = self.T.CallExpression(function=name)
        call.arguments.extend(arguments)
        return self.locate(call, tree)

    def _reference(self, tree: Any, record_type: Any) -> Any:
        parts = tree.parts
        names = [p.name for p in parts]
        known = [f.name for f in record_type.fields] if record_type is not None else []
        known.append(IMPLICIT_FIELD)
        if len(names) == 1 and names[0] in CONSTANTS:
            return self.locate(self.T.NumberLiteral(value=repr(CONSTANTS[names[0]])), tree)
        if len(names) == 2 and names[0] not in NEIGHBOURS and names[0] not in known:
            self.error(parts[0], f"unknown record {names[0]} (write prev.FIELD or next.FIELD)")
            return None
        if len(names) > 2 or (len(names) == 2 and names[0] not in NEIGHBOURS):
            where = parts[2] if names[0] in NEIGHBOURS else parts[1]
            self.error(
                where,
                f"{'.'.join(names)}: attribute chains are not allowed "
                "(write FIELD, prev.FIELD or next.FIELD)",
            )
            return None
        record, field_tree = ("", parts[0]) if len(names) == 1 else (names[0], parts[1])
        field = field_tree.name
        if record_type is not None and field not in known:
            self.error(
                field_tree,
                f"unknown field {field} of {record_type.name} (fields: {', '.join(known)})",
            )
            return None
        return self.locate(self.T.FieldReference(record=record, field=field), tree)

    # -- containers ---------------------------------------------------------------------
    def _container(self, tree: Any) -> Any:
        T = self.T
        robot = _kind(tree) == "RobotContainer"
        container = (T.RobotContainer if robot else T.CloudContainer)(name=tree.name.name)
        self.locate(container, tree.name)
        self.declare(self.containers, container, tree.name, "container")
        container.endpoint = self._endpoint(tree) if robot else None
        if container.endpoint is None:
            container.endpoint = self.locate(T.Endpoint(), tree.name)
        if tree.namespace is not None:
            namespace = _decode(tree.namespace.value)
            self.check(tree.namespace, rosnames.problem_graph_name(namespace, "namespace"))
            container.namespace = namespace
        if not robot:
            self._cloud_settings(container, tree)
        names: dict[str, Any] = {}
        topics: dict[str, Any] = {}
        for member in tree.members:
            kind = _kind(member)
            if kind == "Topic":
                topic = self._topic(member)
                self.declare(topics, topic, member.name, "topic", f" in container {container.name}")
                container.topics.append(topic)
            elif kind == "Store":
                if robot:
                    self.error(
                        member.name,
                        f"store {member.name.name}: stores live in cloud containers",
                    )
                store = self._store(member)
                self.declare(names, store, member.name, "store", f" in container {container.name}")
                container.stores.append(store)
            else:
                node = getattr(self, f"_{kind.lower()}")(member)
                self.declare(names, node, member.name, "node", f" in container {container.name}")
                container.nodes.append(node)
        return container

    def _cloud_settings(self, container: Any, tree: Any) -> None:
        if tree.group is not None:
            group = _decode(tree.group.value)
            if self.check(tree.group, rosnames.problem_group(group)):
                container.group = group
        for attribute in ("size", "cpu", "memory", "bandwidth"):
            value_tree = getattr(tree, attribute)
            if value_tree is None:
                continue
            value = literals.int_literal(value_tree.value, literals.INT32_MAX)
            if value is None:
                limit = literals.INT32_MAX
                self.error(
                    value_tree, f"{attribute} {value_tree.value} is out of range (at most {limit})"
                )
            else:
                container.eSet(attribute, value)

    def _endpoint(self, tree: Any) -> Any:
        endpoint_tree = tree.endpoint
        if endpoint_tree is None:
            return None
        endpoint = self.locate(self.T.Endpoint(), endpoint_tree)
        settings: list[tuple[str, str, Callable[[str], str | None]]] = [
            ("robotId", "robotId", rosnames.problem_robot_id),
            ("url", "url", rosnames.problem_url),
            ("user", "user", rosnames.problem_user),
        ]
        for attribute, feature, problem in settings:
            value_tree = getattr(endpoint_tree, attribute)
            if value_tree is None:
                continue
            value = _decode(value_tree.value)
            if self.check(value_tree, problem(value)):
                endpoint.eSet(feature, value)
        password = endpoint_tree.password
        if password is not None:
            if _kind(password) == "LiteralPassword":
                # The value is a secret: it is neither stored nor repeated in the message.
                self.error(
                    password.literal,
                    'password given as a literal; write password env "VAR"',
                )
            else:
                variable = _decode(password.variable.value)
                if self.check(password.variable, rosnames.problem_env_var(variable)):
                    endpoint.passwordEnv = variable
        return endpoint

    def _topic(self, tree: Any) -> Any:
        name = tree.name.name
        topic = self.locate(self.T.Topic(name=name), tree.name)
        topic.type = self._ros_type(tree.type)
        if tree.rosName is not None:
            ros_name = _decode(tree.rosName.value)
            self.check(tree.rosName, rosnames.problem_graph_name(ros_name, f"topic {name} name"))
        else:
            ros_name = f"/{name}"
            self.check(tree.name, rosnames.problem_graph_name(ros_name, f"topic {name} name"))
        topic.rosName = ros_name
        return topic

    def _ros_type(self, tree: Any) -> str:
        self.check(tree, rosnames.problem_type(tree.value))
        return tree.value

    # -- nodes --------------------------------------------------------------------------
    def _node_common(self, node: Any, tree: Any) -> Any:
        self.locate(node, tree.name)
        node.optional = bool(tree.optional)
        self.check(tree.name, rosnames.problem_base_name(node.name, "node name"))
        return node

    def _node(self, tree: Any) -> Any:
        T = self.T
        node = self._node_common(T.Node(name=tree.name.name), tree)
        node.sharing = T.SharingMode.getEEnumLiteral(tree.sharing or "private")
        self._implementation(node, tree)
        parameters: dict[str, Any] = {}
        interfaces: dict[str, Any] = {}
        for member in tree.members:
            if _kind(member) == "Parameter":
                parameter = self._parameter(member)
                self.declare(
                    parameters, parameter, member.name, "parameter", f" in node {node.name}"
                )
                node.parameters.append(parameter)
            else:
                interface = self._interface(member)
                self.declare(
                    interfaces, interface, member.name, "interface", f" in node {node.name}"
                )
                node.interfaces.append(interface)
                self.trees.append((interface, member))
        return node

    def _implementation(self, node: Any, tree: Any) -> None:
        if tree.implementation is None:
            return
        text = tree.implementation.value
        if self.check(tree.implementation, rosnames.problem_implementation(text)):
            node.package, node.executable = text.split("/", 1)
        if tree.args is not None:
            args = _decode(tree.args.value)
            if self.check(tree.args, rosnames.problem_args(args)):
                node.args = args

    def _parameter(self, tree: Any) -> Any:
        T = self.T
        name = tree.name.name
        parameter = self.locate(
            T.Parameter(name=name, type=T.ParameterType.getEEnumLiteral(tree.type)), tree.name
        )
        self.check(tree.name, rosnames.problem_base_name(name, "parameter name"))
        if tree.value is not None:
            text, problem = _parameter_value(tree.value, tree.type)
            if problem:
                self.error(tree.value, f"parameter {name} is {tree.type}: {problem}")
            else:
                parameter.value = text
        return parameter

    def _interface(self, tree: Any) -> Any:
        kind = {
            "Publishes": "Publisher",
            "Subscribes": "Subscriber",
            "Provides": "ServiceServer",
            "Calls": "ServiceClient",
        }[_kind(tree)]
        name = tree.name.name
        interface = self.locate(getattr(self.T, kind)(name=name), tree.name)
        self.check(tree.name, rosnames.problem_base_name(name, "interface name"))
        if tree.type is not None:
            interface.type = self._ros_type(tree.type)
        if kind == "ServiceServer":
            if tree.rosName is not None:
                ros_name = _decode(tree.rosName.value)
                self.check(tree.rosName, rosnames.problem_graph_name(ros_name, "service name"))
            else:
                ros_name = f"/{name}"
            interface.rosName = ros_name
        return interface

    def _resolve_Publishes(self, interface: Any, tree: Any) -> None:
        self._connect_topic(interface, tree)

    def _resolve_Subscribes(self, interface: Any, tree: Any) -> None:
        self._connect_topic(interface, tree)

    def _resolve_Provides(self, interface: Any, tree: Any) -> None:
        return None  # a server refers to nothing

    def _container_of(self, interface: Any) -> Any:
        return interface.eContainer().eContainer()

    def _topic_in(self, container: Any, ref: Any) -> Any:
        topic = next((t for t in container.topics if t.name == ref.name), None)
        if topic is None:
            self.error(ref, f"unknown topic {ref.name} in container {container.name}")
        return topic

    def _connect_topic(self, interface: Any, tree: Any) -> None:
        if tree.topic is None:
            return
        topic = self._topic_in(self._container_of(interface), tree.topic)
        if topic is None:
            return
        if interface.type and topic.type and interface.type != topic.type:
            self.error(
                tree.topic,
                f"type mismatch: {interface.name} is {interface.type}, "
                f"topic {topic.name} is {topic.type}",
            )
            return
        interface.topic = topic
        interface.type = topic.type

    def _resolve_Calls(self, client: Any, tree: Any) -> None:
        if tree.server is None:
            return
        parts = tree.server.parts
        container = self._container_of(client)
        if len(parts) != 2:
            self.error(tree.server, "expected NODE.SERVER (a server in the same container)")
            return
        node_ref, server_ref = parts
        node = next((n for n in container.nodes if n.name == node_ref.name), None)
        if node is None:
            elsewhere = [
                c.name
                for c in self.system.containers
                if any(n.name == node_ref.name for n in c.nodes)
            ]
            if elsewhere:
                self.error(
                    node_ref,
                    f"node {node_ref.name} is in container {elsewhere[0]}, not in "
                    f"{container.name}: use a bridge (declare 'calls {client.name} : TYPE' "
                    f"and write 'bridge {container.name}.{client.eContainer().name}."
                    f"{client.name} -> {elsewhere[0]}.{node_ref.name}.{server_ref.name}')",
                )
            else:
                self.error(node_ref, f"unknown node {node_ref.name} in container {container.name}")
            return
        server = next((i for i in node.interfaces if i.name == server_ref.name), None)
        if server is None:
            self.error(server_ref, f"unknown server {server_ref.name} of node {node.name}")
            return
        if server.eClass.name != "ServiceServer":
            self.error(
                server_ref,
                f"{node.name}.{server.name} is a {server.eClass.name}, not a service server",
            )
            return
        if client.type and server.type and client.type != server.type:
            self.error(
                server_ref,
                f"type mismatch: {client.name} is {client.type}, "
                f"{node.name}.{server.name} is {server.type}",
            )
            return
        client.server = server
        client.type = server.type

    # -- data acquisition ---------------------------------------------------------------
    def _store(self, tree: Any) -> Any:
        store = self.locate(self.T.Store(name=tree.name.name), tree.name)
        store.optional = bool(tree.optional)
        self.check(tree.name, rosnames.problem_base_name(store.name, "store name"))
        self.trees.append((store, tree))
        return store

    def _resolve_Store(self, store: Any, tree: Any) -> None:
        store.raw = self._data_type_ref(tree.raw)
        outputs: dict[str, Any] = {}
        for refinement_tree in tree.refinements:
            refinement = self.locate(self.T.Refinement(), refinement_tree.output)
            output = self._data_type_ref(refinement_tree.output)
            transform = self.transforms.get(refinement_tree.transform.name)
            if transform is None:
                self.error(
                    refinement_tree.transform,
                    f"unknown transform {refinement_tree.transform.name}",
                )
            if output is not None:
                if output.name in outputs:
                    self.error(
                        refinement_tree.output,
                        f"store {store.name} already refines into {output.name}",
                    )
                outputs[output.name] = refinement
            if (
                transform is not None
                and store.raw is not None
                and transform.input not in (None, store.raw)
            ):
                self.error(
                    refinement_tree.transform,
                    f"transform {transform.name} reads {transform.input.name}, "
                    f"but store {store.name} keeps {store.raw.name}",
                )
            if (
                transform is not None
                and output is not None
                and transform.output not in (None, output)
            ):
                self.error(
                    refinement_tree.transform,
                    f"transform {transform.name} makes {transform.output.name}, not {output.name}",
                )
            refinement.output, refinement.transform = output, transform
            refinement.period = self._period(refinement_tree.period)
            store.refinements.append(refinement)

    def _period(self, tree: Any) -> float | None:
        value = float(tree.value)
        if not math.isfinite(value) or value <= 0 or value > 86400 * 366:
            self.error(tree, f"period {tree.value} s must be positive and at most a year")
            return None
        return value

    def _data_node(self, node: Any, tree: Any, interface_kind: str) -> Any:
        self._node_common(node, tree)
        node.sharing = self.T.SharingMode.private
        records = self.locate(getattr(self.T, interface_kind)(name="records"), tree.topic)
        node.interfaces.append(records)
        self._implementation(node, tree)
        parameters: dict[str, Any] = {}
        for parameter_tree in tree.parameters:
            parameter = self._parameter(parameter_tree)
            self.declare(
                parameters, parameter, parameter_tree.name, "parameter", f" in node {node.name}"
            )
            node.parameters.append(parameter)
        self.trees.append((node, tree))
        return node

    def _writer(self, tree: Any) -> Any:
        return self._data_node(self.T.Writer(name=tree.name.name), tree, "Subscriber")

    def _reader(self, tree: Any) -> Any:
        reader = self._data_node(self.T.Reader(name=tree.name.name), tree, "Publisher")
        reader.period = self._period(tree.period)
        return reader

    def _resolve_data_node(self, node: Any, tree: Any, reads: bool) -> None:
        node.dataType = self._data_type_ref(tree.dataType)
        container = node.eContainer()
        records = node.interfaces[0]
        topic = self._topic_in(container, tree.topic)
        if topic is not None:
            records.topic, records.type = topic, topic.type
        parts = tree.store.parts
        if len(parts) != 2:
            self.error(tree.store, "expected CONTAINER.STORE")
            return
        store_container = self.containers.get(parts[0].name)
        if store_container is None:
            self.error(parts[0], f"unknown container {parts[0].name}")
            return
        store = next((s for s in store_container.stores if s.name == parts[1].name), None)
        if store is None:
            self.error(parts[1], f"unknown store {parts[1].name} in container {parts[0].name}")
            return
        node.store = store
        if node.dataType is None or store.raw is None:
            return
        if not reads and node.dataType is not store.raw:
            self.error(
                tree.dataType,
                f"writer {node.name} writes {node.dataType.name}, but store {store.name} "
                f"takes raw {store.raw.name}",
            )
        kept = [store.raw] + [r.output for r in store.refinements if r.output is not None]
        if reads and node.dataType not in kept:
            names = ", ".join(d.name for d in kept)
            self.error(
                tree.dataType,
                f"store {store.name} keeps no {node.dataType.name} (it keeps {names})",
            )

    def _resolve_Writer(self, node: Any, tree: Any) -> None:
        self._resolve_data_node(node, tree, reads=False)

    def _resolve_Reader(self, node: Any, tree: Any) -> None:
        self._resolve_data_node(node, tree, reads=True)

    # -- bridges ------------------------------------------------------------------------
    def _bridge(self, tree: Any) -> None:
        source, target = tree.source.parts, tree.target.parts
        if len(source) != len(target) or len(source) not in (2, 3):
            self.error(
                tree.source,
                "a bridge is CONTAINER.TOPIC -> CONTAINER.TOPIC or "
                "CONTAINER.NODE.CLIENT -> CONTAINER.NODE.SERVER",
            )
            return
        containers = []
        for ref in (source[0], target[0]):
            container = self.containers.get(ref.name)
            if container is None:
                self.error(ref, f"unknown container {ref.name}")
            containers.append(container)
        if None in containers:
            return
        if containers[0] is containers[1]:
            self.error(target[0], "a bridge connects two different containers")
            return
        if len(source) == 2:
            self._topic_bridge(tree, containers, source[1], target[1])
        else:
            self._service_bridge(tree, containers, source[1:], target[1:])

    def _topic_bridge(self, tree: Any, containers: list, source_ref: Any, target_ref: Any) -> None:
        source = self._topic_in(containers[0], source_ref)
        target = self._topic_in(containers[1], target_ref)
        if source is None or target is None:
            return
        if source.type != target.type:
            self.error(
                target_ref,
                f"type mismatch: {containers[0].name}.{source.name} is {source.type}, "
                f"{containers[1].name}.{target.name} is {target.type}",
            )
            return
        for connection in self.system.connections:
            if (
                getattr(connection.source, "topic", None) is source
                and getattr(connection.target, "topic", None) is target
            ):
                self.error(
                    tree.source,
                    f"duplicate bridge {containers[0].name}.{source.name} -> "
                    f"{containers[1].name}.{target.name} (first at line {connection.srcLine})",
                )
                return
        subscriber = self._endpoint_interface(
            tree, containers[0], "Subscriber", endpoint_subscriber_name(source), "topic", source
        )
        publisher = self._endpoint_interface(
            tree, containers[1], "Publisher", endpoint_publisher_name(target), "topic", target
        )
        if subscriber is not None and publisher is not None:
            self._connect(tree, subscriber, publisher)

    def _member(self, container: Any, node_ref: Any, member_ref: Any) -> Any:
        node = next((n for n in container.nodes if n.name == node_ref.name), None)
        if node is None:
            self.error(node_ref, f"unknown node {node_ref.name} in container {container.name}")
            return None
        member = next((i for i in node.interfaces if i.name == member_ref.name), None)
        if member is None:
            self.error(member_ref, f"node {node.name} has no interface {member_ref.name}")
        return member

    def _service_bridge(self, tree: Any, containers: list, source: list, target: list) -> None:
        client = self._member(containers[0], *source)
        server = self._member(containers[1], *target)
        if client is None or server is None:
            return
        if client.eClass.name != "ServiceClient":
            self.error(
                source[1],
                f"{source[0].name}.{client.name} is a {client.eClass.name}, not a service client",
            )
            return
        if server.eClass.name != "ServiceServer":
            self.error(
                target[1],
                f"{target[0].name}.{server.name} is a {server.eClass.name}, not a service server",
            )
            return
        if client.server is not None:
            if client.server.eContainer() is containers[0].endpoint:
                first = next(c for c in self.system.connections if c.source is client.server)
                self.error(
                    tree.source,
                    f"duplicate bridge for client {source[0].name}.{client.name} "
                    f"(first at line {first.srcLine})",
                )
            else:
                self.error(
                    source[1],
                    f"client {source[0].name}.{client.name} is already bound to "
                    f"{client.server.eContainer().name}.{client.server.name}; declare it "
                    f"unbound ('calls {client.name} : TYPE') to bridge it",
                )
            return
        if client.type and server.type and client.type != server.type:
            self.error(
                target[1],
                f"type mismatch: {client.name} is {client.type}, "
                f"{target[0].name}.{server.name} is {server.type}",
            )
            return
        stand_in = self._endpoint_interface(
            tree, containers[0], "ServiceServer", endpoint_server_name(server), "server", server
        )
        if stand_in is None:
            return
        caller = self._endpoint_interface(
            tree, containers[1], "ServiceClient", endpoint_client_name(server), "server", server
        )
        if caller is None:
            return
        client.server, client.type = stand_in, server.type
        self._connect(tree, stand_in, caller)

    def _endpoint_interface(
        self, tree: Any, container: Any, kind: str, name: str, role: str, target: Any
    ) -> Any:
        """The endpoint interface ``name`` for ``target``: reused when it exists."""
        endpoint = container.endpoint
        existing = next((i for i in endpoint.interfaces if i.name == name), None)
        # An endpoint server is linked to the server it stands in for by its connection.
        if existing is not None:
            if existing.eClass.name == kind and self._serves(existing, role, target):
                return existing
            self.error(
                tree.source,
                f"endpoint interface name {name} in container {container.name} is already "
                f"used by another bridge (line {existing.srcLine}); rename a node, "
                "server or topic",
            )
            return None
        T = self.T
        if kind == "ServiceServer":
            interface = T.ServiceServer(name=name, type=target.type, rosName=target.rosName)
        elif kind == "ServiceClient":
            interface = T.ServiceClient(name=name, type=target.type, server=target)
        else:
            interface = getattr(T, kind)(name=name, type=target.type, topic=target)
        endpoint.interfaces.append(self.locate(interface, tree))
        return interface

    def _serves(self, interface: Any, role: str, target: Any) -> bool:
        if role == "topic":
            return interface.topic is target
        if interface.eClass.name == "ServiceClient":
            return interface.server is target
        return any(
            c.source is interface and c.target.server is target for c in self.system.connections
        )

    def _connect(self, tree: Any, source: Any, target: Any) -> None:
        for connection in self.system.connections:
            if connection.source is source and connection.target is target:
                return
        connection = self.T.EndpointConnection(source=source, target=target)
        self.system.connections.append(self.locate(connection, tree))


def _a(word: str) -> str:
    return f"an {word}" if word[0] in "aeiou" else f"a {word}"


def _parameter_value(tree: Any, ptype: str) -> tuple[str | None, str | None]:
    """(canonical text, None) or (None, what is wrong) for a literal of type ``ptype``."""
    kind = _kind(tree)
    if kind == "StringValue":
        text = _decode(tree.value.value)
        if ptype not in ("string", "yaml"):
            return None, f"expected {_a(ptype)} value, got a string"
        if ptype == "yaml":
            problem = literals.problem_yaml(text)
            if problem:
                return None, problem
        return text, None
    text = tree.value
    if kind == "BoolValue":
        return (
            (text, None) if ptype == "bool" else (None, f"expected {_a(ptype)} value, got {text}")
        )
    if ptype == "int":
        if re.fullmatch(r"[-+]?\d+", text):
            value = literals.int_literal(text)
            if value is not None:
                return str(value), None
            return None, f"{text} is out of range"
        return None, f"expected an int value, got {text}"
    if ptype == "double":
        value = float(text)
        if not math.isfinite(value):
            return None, f"{text} is out of range"
        return repr(value), None
    return None, f"expected {_a(ptype)} value, got {text}"
