"""The ROS names the interfaces of a resolved architecture are bound to.

Launch files remap every connected interface to one of these names, the Rapyuta and
bridge configurations carry data and calls under them, the diagram labels service
calls with them and the smoke rehearsal expects traffic on them: every output of one
product must agree, so the naming rules live here, once.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

from spl.metamodels import tsm
from spl.metamodels.interface_kinds import kind_of
from spl.resolver.architecture.product import topic_ros_name

if TYPE_CHECKING:
    from spl.metamodels import tsm_types


def _endpoint_caller_of(
    stand_in: tsm_types.ServiceServer, system: tsm_types.System
) -> tsm_types.ServiceClient | None:
    """The endpoint client that forwards calls arriving at an endpoint stand-in server."""
    for connection in system.connections:
        target = connection.target
        if connection.source is stand_in and kind_of(target).calls:
            return cast("tsm_types.ServiceClient", target)
    return None


def server_ros_name(server: tsm_types.ServiceServer, system: tsm_types.System) -> str:
    """The ROS name under which ``server`` is offered in its container.

    An endpoint stand-in without a name of its own offers the service under the name
    of the real server it forwards to, so a client calling it keeps working unchanged
    after a migration. A server with no name at all advertises its interface name,
    relative to the container namespace.
    """
    seen: set[int] = set()
    current: tsm_types.ServiceServer | None = server
    while current is not None and id(current) not in seen:
        seen.add(id(current))
        if current.rosName:
            return current.rosName
        if not isinstance(current.eContainer(), tsm().Endpoint):
            return current.name
        caller = _endpoint_caller_of(current, system)
        current = caller.server if caller is not None else None
    return server.name


def remappings(
    node: tsm_types.Node, system: tsm_types.System, ros1: bool = False
) -> list[tuple[str, str]]:
    """``(interface name, ROS name)`` for every connected interface, in model order.

    In ROS 1 (``ros1``) an interface made of several topics (an action's five,
    ``Family.ros1_topics``) is remapped topic by topic, ``NAME/goal`` to ``ROS_NAME/goal``
    and so on: roslaunch remaps a name exactly, never the names under it."""
    rules = []
    for interface in node.interfaces:
        kind = kind_of(interface)
        bound = kind.bound_to(interface)
        rule: tuple[str, str] | None = None
        if kind.on_topic:
            if bound is not None:
                rule = (interface.name, topic_ros_name(bound))
        elif kind.serves:
            server = cast("tsm_types.ServiceServer", interface)
            if server.rosName:
                rule = (interface.name, server.rosName)
        elif kind.calls and bound is not None:
            rule = (interface.name, server_ros_name(bound, system))
        if rule is None:
            continue
        parts = kind.family.ros1_topics if ros1 else ()
        rules.extend([(f"{rule[0]}/{p.suffix}", f"{rule[1]}/{p.suffix}") for p in parts] or [rule])
    return rules


def in_namespace(name: str, namespace: str | None) -> str:
    """``name`` as seen from a container's namespace (global and private names stay)."""
    if not namespace or name.startswith(("/", "~")):
        return name
    return f"/{namespace.strip('/')}/{name}"


def resolved_topic_name(topic: tsm_types.Topic) -> str:
    """The topic's ROS name as the launch files remap to it, in its container's namespace."""
    container = cast("tsm_types.Container", topic.eContainer())  # a topic of the system
    return in_namespace(topic_ros_name(topic), container.namespace)


def resolved_service_name(
    server: tsm_types.ServiceServer, container: tsm_types.Container, system: tsm_types.System
) -> str:
    """The ROS name a server (or endpoint stand-in) is called by in ``container``."""
    return in_namespace(server_ros_name(server, system), container.namespace)
