"""Containers of the .tsm language: robots and cloud instances with what they hold.

A robot container may carry the endpoint a cloud connects to (robot id, URL, user and
the environment variable holding the password: a password written in the file is
refused, as it would be copied into every generated configuration); a cloud container
carries its Rapyuta deployment settings. Both hold topics, nodes, writers and readers;
only a cloud container holds stores.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, cast

from spl.dsl import literals, rosnames
from spl.dsl.tsm import data as tsm_data, nodes as tsm_nodes
from spl.dsl.tsm.names import Names
from spl.dsl.tsm.syntax import decode, kind

if TYPE_CHECKING:
    from spl.dsl.tsm import tree as tsm_tree

# How each rule of the grammar's ``Member`` (but a topic) becomes a model element,
# and what it is called in a duplicate-name message.
_MEMBERS: dict[str, tuple[Callable[[Names, Any], Any], str]] = {
    "Node": (tsm_nodes.node, "node"),
    "Writer": (tsm_data.writer, "node"),
    "Reader": (tsm_data.reader, "node"),
    "Store": (tsm_data.store, "store"),
}


def container(names: Names, tree: tsm_tree.RobotContainer | tsm_tree.CloudContainer) -> Any:
    """The RobotContainer or CloudContainer of a ``container`` block and its members."""
    T = names.T
    robot = kind(tree) == "RobotContainer"
    container = (T.RobotContainer if robot else T.CloudContainer)(name=tree.name.name)
    names.locate(container, tree.name)
    names.declare(names.containers, container, tree.name, "container")
    twin = next(
        (
            c
            for n, c in names.containers.items()
            if n != container.name and n.lower() == container.name.lower()
        ),
        None,
    )
    if twin is not None:  # bundle files are named after containers
        names.error(
            tree.name,
            f"container name {container.name} differs from {twin.name} (line {twin.srcLine}) "
            "only in case: their bundle files (ros1/<container>.launch, ...) would be one file "
            "on a case-insensitive file system",
        )
    endpoint = _endpoint(names, cast("tsm_tree.RobotContainer", tree)) if robot else None
    container.endpoint = endpoint if endpoint is not None else names.locate(T.Endpoint(), tree.name)
    if tree.namespace is not None:
        namespace = decode(tree.namespace.value)
        names.check(tree.namespace, rosnames.problem_graph_name(namespace, "namespace"))
        container.namespace = namespace
    if not robot:
        _cloud_settings(names, container, cast("tsm_tree.CloudContainer", tree))
    members: dict[str, Any] = {}  # nodes and stores share one namespace
    topics = names.topics[id(container)] = {}
    nodes = names.nodes[id(container)] = {}
    by_ros_name: dict[str, Any] = {}
    where = f" in container {container.name}"
    for member in tree.members:
        rule = kind(member)
        if rule == "Topic":
            topic = _topic(names, cast("tsm_tree.Topic", member))
            names.declare(topics, topic, member.name, "topic", where)
            container.topics.append(topic)
            first = by_ros_name.setdefault(topic.rosName, topic)
            clash = first is not topic and None not in (first.type, topic.type)
            if clash and first.type != topic.type:
                names.error(member.name, ros_name_clash(topic, first))
            continue
        if rule == "Store" and robot:
            names.error(
                member.name,
                f"store {member.name.name}: stores live in cloud containers",
            )
        build, what = _MEMBERS[rule]
        element = build(names, member)
        names.declare(members, element, member.name, what, where)
        if rule == "Store":
            container.stores.append(element)
        else:
            nodes.setdefault(element.name, element)
            container.nodes.append(element)
    return container


def _cloud_settings(names: Names, container: Any, tree: tsm_tree.CloudContainer) -> None:
    if tree.group is not None:
        group = decode(tree.group.value)
        if names.check(tree.group, rosnames.problem_group(group)):
            container.group = group
    for attribute in ("size", "cpu", "memory", "bandwidth"):
        value_tree = getattr(tree, attribute)
        if value_tree is None:
            continue
        value = literals.int_literal(value_tree.value, literals.INT32_MAX)
        if value is None:
            limit = literals.INT32_MAX
            names.error(
                value_tree, f"{attribute} {value_tree.value} is out of range (at most {limit})"
            )
        else:
            container.eSet(attribute, value)


def _endpoint(names: Names, tree: tsm_tree.RobotContainer) -> Any:
    endpoint_tree = tree.endpoint
    if endpoint_tree is None:
        return None
    endpoint = names.locate(names.T.Endpoint(), endpoint_tree)
    settings: list[tuple[str, str, Callable[[str], str | None]]] = [
        ("robotId", "robotId", rosnames.problem_robot_id),
        ("url", "url", rosnames.problem_url),
        ("user", "user", rosnames.problem_user),
    ]
    for attribute, feature, problem in settings:
        value_tree = getattr(endpoint_tree, attribute)
        if value_tree is None:
            continue
        value = decode(value_tree.value)
        if names.check(value_tree, problem(value)):
            endpoint.eSet(feature, value)
    password = endpoint_tree.password
    if password is not None:
        if kind(password) == "LiteralPassword":
            # The value is a secret: it is neither stored nor repeated in the message.
            names.error(
                cast("tsm_tree.LiteralPassword", password).literal,
                'password given as a literal; write password env "VAR"',
            )
        else:
            written = cast("tsm_tree.EnvPassword", password).variable
            variable = decode(written.value)
            if names.check(written, rosnames.problem_env_var(variable)):
                endpoint.passwordEnv = variable
    return endpoint


def _topic(names: Names, tree: tsm_tree.Topic) -> Any:
    name = tree.name.name
    topic = names.locate(names.T.Topic(name=name), tree.name)
    topic.type = tsm_nodes.ros_type(names, tree.type)
    if tree.rosName is not None:
        ros_name = decode(tree.rosName.value)
        names.check(tree.rosName, rosnames.problem_graph_name(ros_name, f"topic {name} name"))
    else:
        ros_name = f"/{name}"
        names.check(tree.name, rosnames.problem_graph_name(ros_name, f"topic {name} name"))
    topic.rosName = ros_name
    return topic


def ros_name_clash(topic: Any, first: Any) -> str:
    """Two topics of one container under one ROS name with two message types: ROS has one
    topic there, and its subscribers would get messages of the wrong type."""
    return (
        f"topic {topic.name} is {topic.rosName}, as topic {first.name} (line {first.srcLine}) "
        f"is, but carries {topic.type}, not {first.type}: one ROS topic carries one message type"
    )
