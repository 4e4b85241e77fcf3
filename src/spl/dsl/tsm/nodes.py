"""ROS nodes of the .tsm language: implementation, parameters and interfaces.

Every value a node carries ends up in a launch file or a Rapyuta configuration, so
each is checked here against ROS's own rules (``rosnames``) and the parameter's
declared type, and reported at its column. An interface names its topic (or, for a
client, the server it calls) in its own container; those references are resolved
once every node and topic of the file is declared.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, cast

from spl.dsl import literals, rosnames
from spl.dsl.tsm.calling import call_problem
from spl.dsl.tsm.names import Names, find_interface
from spl.dsl.tsm.options import INTERFACE_OPTIONS, Option
from spl.dsl.tsm.syntax import decode, kind
from spl.metamodels.interface_kinds import KINDS, InterfaceKind, kind_of

if TYPE_CHECKING:
    from spl.dsl.tsm import tree as tsm_tree


def node_common(
    names: Names, node: Any, tree: tsm_tree.Node | tsm_tree.Writer | tsm_tree.Reader
) -> Any:
    """What every kind of node declares: where it is, whether optional, a valid name."""
    names.locate(node, tree.name)
    node.optional = bool(tree.optional)
    names.check(tree.name, rosnames.problem_base_name(node.name, "node name"))
    return node


def node(names: Names, tree: tsm_tree.Node) -> Any:
    """The Node of a ``node`` block with its parameters and interfaces."""
    T = names.T
    node = node_common(names, T.Node(name=tree.name.name), tree)
    node.sharing = names.literal("SharingMode", tree.sharing or "private")
    implementation(names, node, tree)
    parameters(
        names, node, [cast("tsm_tree.Parameter", m) for m in tree.members if kind(m) == "Parameter"]
    )
    interfaces: dict[str, Any] = {}
    where = f" in node {node.name}"
    for member in tree.members:
        rule = kind(member)
        if rule == "Parameter":
            continue
        interface_kind = next(k for k in KINDS if k.rule == rule)
        interface = _interface(names, interface_kind, cast("tsm_tree.Publishes", member))
        names.declare(interfaces, interface, member.name, "interface", where)
        node.interfaces.append(interface)
        resolve = _resolver(interface_kind)
        if resolve is not None:
            names.later(resolve, interface, member)
    return node


def parameters(names: Names, node: Any, parameter_trees: list[tsm_tree.Parameter]) -> None:
    """Declare ``parameter_trees`` as the parameters of ``node``."""
    declared: dict[str, Any] = {}
    where = f" in node {node.name}"
    for parameter_tree in parameter_trees:
        parameter = _parameter(names, parameter_tree)
        names.declare(declared, parameter, parameter_tree.name, "parameter", where)
        node.parameters.append(parameter)


def implementation(
    names: Names, node: Any, tree: tsm_tree.Node | tsm_tree.Writer | tsm_tree.Reader
) -> None:
    """The ``implementation package/executable args "..."`` of a node, when given."""
    if tree.implementation is None:
        return
    text = tree.implementation.value
    if names.check(tree.implementation, rosnames.problem_implementation(text)):
        node.package, node.executable = text.split("/", 1)
    if tree.args is not None:
        args = decode(tree.args.value)
        if names.check(tree.args, rosnames.problem_args(args)):
            node.args = args


def ros_type(names: Names, tree: Any) -> str:
    """A message or service type ``package/Type``, checked."""
    names.check(tree, rosnames.problem_type(tree.value))
    return tree.value


def _parameter(names: Names, tree: tsm_tree.Parameter) -> Any:
    T = names.T
    name = tree.name.name
    parameter = names.locate(
        T.Parameter(name=name, type=names.literal("ParameterType", tree.type)), tree.name
    )
    names.check(tree.name, rosnames.problem_base_name(name, "parameter name"))
    if tree.value is not None:
        text, problem = _parameter_value(tree.value, tree.type)
        if problem:
            names.error(tree.value, f"parameter {name} is {tree.type}: {problem}")
        else:
            parameter.value = text
    return parameter


def _a(word: str) -> str:
    return f"an {word}" if word[0] in "aeiou" else f"a {word}"


def _parameter_value(tree: Any, ptype: str) -> tuple[str | None, str | None]:
    """(canonical text, None) or (None, what is wrong) for a literal of type ``ptype``."""
    rule = kind(tree)
    if rule == "StringValue":
        text = decode(tree.value.value)
        if ptype not in ("string", "yaml"):
            return None, f"expected {_a(ptype)} value, got a string"
        if ptype == "yaml":
            problem = literals.problem_yaml(text)
            if problem:
                return None, problem
        return text, None
    text = tree.value
    if rule == "BoolValue":
        return (
            (text, None) if ptype == "bool" else (None, f"expected {_a(ptype)} value, got {text}")
        )
    if ptype == "int":
        if re.fullmatch(r"[-+]?\d+", text):
            value = literals.int_literal(text, literals.ROS_INT_MAX)
            if value is not None:
                return str(value), None
            return None, f"{text} is out of range: {literals.ROS_INT_RANGE}"
        return None, f"expected an int value, got {text}"
    if ptype == "double":
        number = float(text)
        if not math.isfinite(number):
            return None, f"{text} is out of range"
        return repr(number), None
    return None, f"expected {_a(ptype)} value, got {text}"


# -- interfaces ---------------------------------------------------------------------------
def _interface(
    names: Names,
    interface_kind: InterfaceKind,
    tree: tsm_tree.Publishes | tsm_tree.Subscribes | tsm_tree.Provides | tsm_tree.Calls,
) -> Any:
    """The interface of a node's statement ``tree`` (its rule is ``interface_kind``'s)."""
    name = tree.name.name
    interface = names.locate(getattr(names.T, interface_kind.eclass)(name=name), tree.name)
    names.check(tree.name, rosnames.problem_base_name(name, "interface name"))
    if tree.type is not None:
        interface.type = ros_type(names, tree.type)
        _refuse_generated_type(names, interface_kind, interface, tree.type)
    external: tsm_tree.Str | None = getattr(tree, "external", None)
    if external is not None:  # an input fed from outside the architecture (docs/tsm.md)
        reason = decode(external.value).strip()
        missing = "external needs a reason: what outside the architecture feeds this input"
        if names.check(external, None if reason else missing):
            interface.external = reason
    if interface_kind.serves:  # a server has a ROS name of its own; a client takes its server's
        written = cast("tsm_tree.Provides", tree).rosName
        if written is not None:
            ros_name = decode(written.value)
            what = f"{interface_kind.family.name} name"
            names.check(written, rosnames.problem_graph_name(ros_name, what))
        else:
            ros_name = f"/{name}"
        interface.rosName = ros_name
    for option in INTERFACE_OPTIONS[interface_kind.rule]:
        value = getattr(tree, option.attribute)
        if value is not None and option.attribute not in _CHECKED_HERE:
            _plain_option(names, interface, option, value)
    return interface


# the options of an interface statement this module checks by their own rules, above
_CHECKED_HERE = frozenset({"external", "rosName"})


def _plain_option(names: Names, element: Any, option: Option, tree: Any) -> None:
    """An option with no rule of its own beyond its type: copied into the model's
    attribute of its name, in the range of the metamodel's type (docs/architecture.md,
    "Adding one .tsm element, end to end")."""
    feature = element.eClass.findEStructuralFeature(option.attribute)
    if feature is None:
        raise LookupError(f"tsm.ecore: {element.eClass.name} has no {option.attribute}")
    text, kind_name = tree.value, feature.eType.name
    value: Any = None
    if kind_name == "EString":
        value = decode(text) if option.quoted else text
    elif kind_name in ("EInt", "EIntegerObject"):
        value = literals.int_literal(text, literals.INT32_MAX)
    elif kind_name in ("EDouble", "EDoubleObject"):
        number = float(text)
        value = number if math.isfinite(number) else None
    elif kind_name == "EBoolean":
        value = text == "true"
    if value is None:
        names.error(tree, f"{option.keyword} {text} is out of range of {kind_name}")
        return
    element.eSet(option.attribute, value)


def _refuse_generated_type(
    names: Names, interface_kind: InterfaceKind, interface: Any, tree: tsm_tree.TypeRef
) -> None:
    """A type ROS generates from the interface's own (``MoveBaseAction`` from the action
    ``MoveBase``) is refused with the type to write instead (docs/tsm.md, "Actions"); the
    interface takes that type, so its bindings are not refused for it once more."""
    package, _, name = interface.type.partition("/")
    for ending in interface_kind.family.generated_types:
        if name.endswith(ending) and len(name) > len(ending):
            own = f"{package}/{name[: -len(ending)]}"
            names.error(
                tree,
                f"{interface_kind.title} {interface.name}: {interface.type} is the {ending} "
                f"message generated from {own}; write the {interface_kind.family.name}'s own "
                f"type, {own}",
            )
            interface.type = own
            return


def _container_of(interface: Any) -> Any:
    return interface.eContainer().eContainer()


def _connect_topic(
    names: Names, interface: Any, tree: tsm_tree.Publishes | tsm_tree.Subscribes
) -> None:
    """A publisher's or subscriber's topic, of its own container; the types must agree."""
    if tree.topic is None:
        return
    topic = names.topic(_container_of(interface), tree.topic)
    if topic is not None:
        _bind(names, interface, "topic", topic, tree.topic, f"topic {topic.name}")


def _bind(names: Names, interface: Any, role: str, target: Any, ref: Any, named: str) -> None:
    """``interface.ROLE = target`` (its topic, or the server a client calls) when their
    types agree; the interface takes the target's type."""
    if interface.type and target.type and interface.type != target.type:
        names.error(
            ref, f"type mismatch: {interface.name} is {interface.type}, {named} is {target.type}"
        )
        return
    setattr(interface, role, target)
    if interface.type != target.type:  # unless declared so already
        interface.type = target.type


def _connect_server(names: Names, client: Any, tree: tsm_tree.Calls) -> None:
    """The server a client calls: NODE.SERVER in the client's own container."""
    if tree.server is None:
        return
    parts = tree.server.parts
    container = _container_of(client)
    client_kind = kind_of(client)
    if len(parts) != 2:
        names.error(tree.server, "expected NODE.SERVER (a server in the same container)")
        return
    node_ref, server_ref = parts
    node = names.find_node(container, node_ref.name)
    if node is None:
        elsewhere = [c.name for c in names.system.containers if node_ref.name in names.nodes[id(c)]]
        if elsewhere:
            names.error(
                node_ref,
                f"node {node_ref.name} is in container {elsewhere[0]}, not in "
                f"{container.name}: use a bridge (declare "
                f"'{client_kind.keyword} {client.name} : TYPE' "
                f"and write 'bridge {container.name}.{client.eContainer().name}."
                f"{client.name} -> {elsewhere[0]}.{node_ref.name}.{server_ref.name}')",
            )
        else:
            names.error(node_ref, f"unknown node {node_ref.name} in container {container.name}")
        return
    server = find_interface(node, server_ref.name)
    if server is None:
        names.error(server_ref, f"unknown server {server_ref.name} of node {node.name}")
        return
    problem = call_problem(client, server)
    if problem is not None:
        names.error(server_ref, problem.message)
        return
    _bind(names, client, "server", server, server_ref, f"{node.name}.{server.name}")


def _resolver(interface_kind: InterfaceKind) -> Callable[[Names, Any, Any], None] | None:
    """What an interface of ``interface_kind`` refers to, resolved once every name of the
    file is declared: a topic, or the server it calls (a server refers to nothing)."""
    if interface_kind.on_topic:
        return _connect_topic
    return _connect_server if interface_kind.calls else None
