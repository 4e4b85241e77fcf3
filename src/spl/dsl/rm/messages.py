"""The messages and agreement rules the .rm builder and the Resolution Engine share.

A statement the .rm builder refuses when it fails wherever its node can be, and the
Resolution Engine refuses in the one product it derives, is worded once here, so
``spl check``, ``spl resolve`` and the editor say the same thing (docs/semantics.md).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import location_of
from spl.dsl.tsm.calling import declared_name

if TYPE_CHECKING:
    from spl.metamodels import tsm_types
    from spl.metamodels.model_types import EObject

    # a topic a statement may meet: the .tsm's, or a `new topic` declaration
    Typed = tsm_types.Interface | tsm_types.Topic


def at(element: EObject) -> str:
    """Where a model element is declared, as messages cite it (``file:line:col``)."""
    return str(location_of(element))


def candidates(found: list[tuple[str, EObject]]) -> str:
    """``Alpha.Camera (t.tsm:11:10) or Beta.Camera (t.tsm:28:10)``: every candidate of an
    ambiguous reference with its location."""
    return " or ".join(f"{label} ({at(element)})" for label, element in found)


def missing_topic(name: str, node: tsm_types.Node, places: list[tsm_types.Container]) -> str:
    """The message for topic ``name`` found in none of the containers ``node`` can be in."""
    if len(places) == 1:
        return f"unknown topic {name} in container {places[0].name}"
    where = " or ".join(c.name for c in places)
    return f"unknown topic {name} in container {where} (where {node.name} can be at this point)"


def agree(a: Typed, b: Typed) -> bool:
    """Two typed elements (interface, topic, server) agree unless both have different types."""
    return not (a.type and b.type and a.type != b.type)


def same_topic(a: tsm_types.Topic, b: tsm_types.Topic) -> bool:
    """Two `new topic` declarations create one topic when type and ROS name agree."""
    return (a.type, a.rosName) == (b.type, b.rosName)


def new_topic_clash(
    name: str, container: tsm_types.Container, existing: tsm_types.Topic, created: bool
) -> str:
    if created:
        return (
            f"new topic {name} in {container.name} is declared again with another type or "
            f"ROS name (first at {at(existing)})"
        )
    return (
        f"new topic {name}: container {container.name} already has a topic named {name} "
        f"({at(existing)}; connect to it with 'to topic {name}')"
    )


def new_topic_ros_name_clash(
    name: str, container: tsm_types.Container, other: tsm_types.Topic, topic: tsm_types.Topic
) -> str:
    """A `new topic` under the ROS name of a topic of another type in its container: ROS has
    one topic there, and its subscribers would get messages of the wrong type."""
    return (
        f"new topic {name} is {topic.rosName} in container {container.name}, as topic "
        f"{other.name} is ({at(other)}), but carries {topic.type}, not {other.type}: one ROS "
        "topic carries one message type"
    )


def not_served_here(
    client: tsm_types.ServiceClient,
    server: tsm_types.ServiceServer,
    server_places: list[tsm_types.Container],
    client_places: list[tsm_types.Container],
) -> str:
    """``connect CLIENT to server SERVER`` whose two nodes are in different containers."""
    served = " or ".join(c.name for c in server_places)
    calling = " or ".join(c.name for c in client_places)
    return (
        f"{_node(server).name}.{server.name} is served in container {served}, not in "
        f"{calling}: use 'connect bridge {declared_name(client)} -> {declared_name(server)}'"
    )


def same_container_bridge(
    client: tsm_types.ServiceClient,
    server: tsm_types.ServiceServer,
    container: tsm_types.Container,
) -> str:
    return (
        f"a bridge connects two different containers: {_node(client).name}."
        f"{client.name} and {_node(server).name}.{server.name} are both in "
        f"{container.name} at this point (connect them with 'to server')"
    )


def name_taken(node: tsm_types.Node, target: tsm_types.Container, resident: tsm_types.Node) -> str:
    return (
        f"cannot migrate {node.name} to {target.name}: container {target.name} already has a "
        f"node {resident.name} ({at(resident)})"
    )


def _node(interface: tsm_types.Interface) -> tsm_types.Node:
    """The node of an interface the .rm names (a node's, never an endpoint's)."""
    return cast("tsm_types.Node", interface.eContainer())
