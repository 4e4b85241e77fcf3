"""Write a ``tsm.System`` back as .tsm text that parses to the same model.

The resolved architecture of a product is written as ``resolved.tsm`` in the bundle,
so a user can read (and re-check) exactly what was derived. Defaults are left out
(ROS names equal to ``/NAME``, ``sharing private``); endpoint interfaces and
endpoint connections are written back as the ``bridge`` statements they come from.
Elements are printed in model order, so the same model always gives the same bytes.
"""

from __future__ import annotations

import re
from typing import Any

from spl.dsl.tsm.bridges import bridged_clients
from spl.dsl.tsm.options import INTERFACE_OPTIONS, Option
from spl.metamodels.interface_kinds import kind_of

_INDENT = "    "

# Binding strength of each expression operator, loosest first (mirrors tsm.tx).
_PRECEDENCE = {
    "or": 1,
    "and": 2,
    "not": 3,
    "<": 4,
    "<=": 4,
    ">": 4,
    ">=": 4,
    "==": 4,
    "!=": 4,
    "+": 5,
    "-": 5,
    "*": 6,
    "/": 6,
    "%": 6,
}
_UNARY_MINUS = 7
_ATOM = 8


def print_model(system: Any) -> str:
    """The .tsm text of ``system``."""
    blocks: list[str] = []
    if system.name:
        blocks.append(f"system {system.name}")
    blocks += [_data_type(d) for d in system.dataTypes]
    blocks += [_transform(t) for t in system.transforms]
    blocks += [_container(c) for c in system.containers]
    bridges = _bridges(system)
    if bridges:
        blocks.append("\n".join(bridges))
    return "\n\n".join(blocks) + "\n"


def _quote(text: str) -> str:
    escapes = {'"': '\\"', "\\": "\\\\", "\n": "\\n", "\t": "\\t"}
    return '"' + re.sub(r'["\\\n\t]', lambda m: escapes[m.group(0)], text) + '"'


def _number(value: float) -> str:
    if value == int(value) and abs(value) < 1e15:
        return str(int(value))
    return repr(value)


# -- data acquisition -------------------------------------------------------------------
def _data_type(data_type: Any) -> str:
    lines = [f"data {data_type.name} {{"]
    lines += [f"{_INDENT}{f.name} : {f.type.name}" for f in data_type.fields]
    return "\n".join([*lines, "}"])


def _transform(transform: Any) -> str:
    lines = [f"transform {transform.name} : {transform.input.name} -> {transform.output.name} {{"]
    lines += [
        f"{_INDENT}{a.field} = {expression_text(a.expression)}" for a in transform.assignments
    ]
    return "\n".join([*lines, "}"])


def expression_text(expression: Any) -> str:
    """An expression in .tsm syntax with the fewest parentheses that keep its tree."""
    return _expression(expression)[0]


def _expression(expression: Any) -> tuple[str, int]:
    kind = expression.eClass.name
    if kind == "NumberLiteral":
        return expression.value, _ATOM
    if kind == "BooleanLiteral":
        return ("true" if expression.value else "false"), _ATOM
    if kind == "FieldReference":
        prefix = f"{expression.record}." if expression.record else ""
        return prefix + expression.field, _ATOM
    if kind == "CallExpression":
        arguments = ", ".join(_expression(a)[0] for a in expression.arguments)
        return f"{expression.function}({arguments})", _ATOM
    if kind == "UnaryExpression":
        if expression.operator == "not":
            text, level = _expression(expression.operand)
            return f"not {_wrap(text, level, _PRECEDENCE['not'])}", _PRECEDENCE["not"]
        text, level = _expression(expression.operand)
        return f"-{_wrap(text, level, _UNARY_MINUS + 1)}", _UNARY_MINUS
    level = _PRECEDENCE[expression.operator]
    left, left_level = _expression(expression.left)
    right, right_level = _expression(expression.right)
    comparison = level == _PRECEDENCE["<"]
    # Left-associative: the left operand may share the level (not for comparisons, which
    # do not chain); the right operand must bind tighter.
    left = _wrap(left, left_level, level + 1 if comparison else level)
    right = _wrap(right, right_level, level + 1)
    return f"{left} {expression.operator} {right}", level


def _wrap(text: str, level: int, needed: int) -> str:
    return text if level >= needed else f"({text})"


# -- containers ---------------------------------------------------------------------------
def _container(container: Any) -> str:
    robot = container.eClass.name == "RobotContainer"
    if robot:
        header = f"robot container {container.name} {{"
    else:
        settings = [f"group {_quote(container.group)}"] if container.group else []
        for attribute in ("size", "cpu", "memory", "bandwidth"):
            value = container.eGet(attribute)
            if value is not None:
                settings.append(f"{attribute} {value}")
        header = " ".join(["cloud container", container.name, *settings, "{"])
    lines = [header]
    if robot and container.endpoint is not None:
        endpoint = _endpoint(container.endpoint)
        if endpoint:
            lines.append(f"{_INDENT}{endpoint}")
    if container.namespace:
        lines.append(f"{_INDENT}namespace {_quote(container.namespace)}")
    sections = []
    if container.topics:
        sections.append([_INDENT + _topic(t) for t in container.topics])
    sections += [_indent(_node(n)) for n in container.nodes]
    sections += [_indent(_store(s)) for s in container.stores]
    for section in sections:
        lines += ["", *section] if len(lines) > 1 else section
    return "\n".join([*lines, "}"])


def _indent(lines: list[str]) -> list[str]:
    return [_INDENT + line for line in lines]


def _endpoint(endpoint: Any) -> str:
    parts = []
    if endpoint.robotId:
        parts.append(f"robot_id {_quote(endpoint.robotId)}")
    if endpoint.url:
        parts.append(f"url {_quote(endpoint.url)}")
    if endpoint.user:
        parts.append(f"user {_quote(endpoint.user)}")
    if endpoint.passwordEnv:
        parts.append(f"password env {_quote(endpoint.passwordEnv)}")
    return " ".join(["endpoint", *parts]) if parts else ""


def _topic(topic: Any) -> str:
    text = f"topic {topic.name} : {topic.type}"
    if topic.rosName and topic.rosName != f"/{topic.name}":
        text += f" name {_quote(topic.rosName)}"
    return text


def _node(node: Any) -> list[str]:
    kind = node.eClass.name
    if kind in ("Writer", "Reader"):
        return _data_node(node)
    optional = "optional " if node.optional else ""
    sharing = (
        f" sharing {node.sharing.name}" if node.sharing and node.sharing.name != "private" else ""
    )
    lines = [f"{optional}node {node.name}{sharing} {{", *_implementation(node)]
    lines += [_INDENT + _parameter(p) for p in node.parameters]
    lines += [_INDENT + _interface(i) for i in node.interfaces]
    return [*lines, "}"]


def _implementation(node: Any) -> list[str]:
    if not (node.package or node.executable):
        return []
    implementation = f"implementation {node.package}/{node.executable}"
    if node.args:
        implementation += f" args {_quote(node.args)}"
    return [_INDENT + implementation]


def _parameter(parameter: Any) -> str:
    ptype = parameter.type.name
    text = f"param {parameter.name} : {ptype}"
    if parameter.value is not None:
        value = _quote(parameter.value) if ptype in ("string", "yaml") else parameter.value
        text += f" = {value}"
    return text


def _typed(interface: Any, peer_type: str | None) -> str:
    """`` : TYPE`` when the interface's own type is not the one its peer gives it."""
    return f" : {interface.type}" if interface.type and interface.type != peer_type else ""


def _interface(interface: Any) -> str:
    """An interface's line, then the options its statement closes with as ``tsm.tx``
    declares them (an input fed from outside keeps its reason, docs/tsm.md), each left
    out where it has its metamodel's default; a server's ROS name is ``_wired``'s."""
    text = _wired(interface)
    for option in INTERFACE_OPTIONS[kind_of(interface).rule]:
        if option.attribute != "rosName":
            text += _option(interface, option)
    return text


def _option(element: Any, option: Option) -> str:
    """`` KEYWORD value`` of a set option, in the syntax of its value's rule."""
    value = element.eGet(option.attribute)
    feature = element.eClass.findEStructuralFeature(option.attribute)
    if value is None or value == "" or value == feature.get_default_value():
        return ""
    if option.quoted:
        written = _quote(value)
    elif isinstance(value, bool):
        written = "true" if value else "false"
    else:
        written = _number(value) if isinstance(value, float) else str(value)
    return f" {option.keyword} {written}"


def _wired(interface: Any) -> str:
    """The statement of ``interface``'s kind (docs/tsm.md), with what it is bound to."""
    kind, name = kind_of(interface), interface.name
    if kind.binds is None:  # a server: bound to nothing, answering under its ROS name
        text = f"{kind.keyword} {name} : {interface.type}"
        if interface.rosName and interface.rosName != f"/{name}":
            text += f" name {_quote(interface.rosName)}"
        return text
    bound = kind.bound_to(interface)
    if bound is None or bound.eContainer().eClass.name == "Endpoint":
        return f"{kind.keyword} {name} : {interface.type}"  # unbound, or bound by a bridge
    # a topic of the same container, or the server called: NODE.SERVER
    where = bound.name if kind.on_topic else f"{bound.eContainer().name}.{bound.name}"
    return f"{kind.keyword} {name}{_typed(interface, bound.type)} {kind.arrow} {where}"


def _store(store: Any) -> list[str]:
    optional = "optional " if store.optional else ""
    lines = [f"{optional}store {store.name} {{", f"{_INDENT}raw {store.raw.name}"]
    for refinement in store.refinements:
        lines.append(
            f"{_INDENT}refined {refinement.output.name} by {refinement.transform.name} "
            f"every {_number(refinement.period)} s"
        )
    return [*lines, "}"]


def _data_node(node: Any) -> list[str]:
    optional = "optional " if node.optional else ""
    records = next((i for i in node.interfaces if i.name == "records"), None)
    topic = records.topic.name if records is not None and records.topic is not None else "?"
    store = f"{node.store.eContainer().name}.{node.store.name}"
    if node.eClass.name == "Writer":
        text = f"{optional}writer {node.name} : {node.dataType.name} to {store} <- {topic}"
    else:
        text = (
            f"{optional}reader {node.name} : {node.dataType.name} from {store} -> {topic} "
            f"{'subscribe ' if node.subscribe else ''}every {_number(node.period)} s"
        )
    body = _implementation(node) + [_INDENT + _parameter(p) for p in node.parameters]
    return [f"{text} {{", *body, "}"] if body else [text]


# -- bridges ------------------------------------------------------------------------------
def _bridges(system: Any) -> list[str]:
    lines = []
    for connection in system.connections:
        source, target = connection.source, connection.target
        source_container = source.eContainer().eContainer()
        target_container = target.eContainer().eContainer()
        if kind_of(source).on_topic:  # a topic's bridge, else a stand-in server's
            lines.append(
                f"bridge {source_container.name}.{source.topic.name} -> "
                f"{target_container.name}.{target.topic.name}"
            )
            continue
        server = target.server
        where = f"{target_container.name}.{server.eContainer().name}.{server.name}"
        for node, client in bridged_clients(source):
            lines.append(f"bridge {source_container.name}.{node.name}.{client.name} -> {where}")
    return lines
