"""ROS 1 launch files: one roslaunch XML file per container of a resolved product.

The XML is built as an lxml tree, never by string concatenation, so no model text can
add markup. Escaping XML is not enough for roslaunch, though: it expands ``$(...)``
substitution args in every attribute (``$(eval ...)`` runs Python) and has no escape
for ``$``; it also strips ``<param value>``. A string parameter value containing ``$``
or surrounding blanks is therefore written as a ``<rosparam>`` whose YAML text
roslaunch takes as written, and any other attribute that would carry a ``$`` is
refused.

The remapping rules here (which ROS name every connected interface is bound to) are
shared with the ROS 2 generator, so both launch flavours of one product agree.
"""

from __future__ import annotations

import json
import math
import re
from typing import Any

import yaml
from lxml import etree

from spl import __version__
from spl.metamodels import tsm
from spl.resolver.product import ResolvedProduct

__all__ = [
    "generate",
    "header_text",
    "launch_document",
    "launch_file",
    "remappings",
    "serialize",
    "server_ros_name",
    "topic_ros_name",
]

ROS1_TYPES = {"string": "str", "int": "int", "double": "double", "bool": "bool", "yaml": "yaml"}
BOOL_TEXT = {"true", "false"}


def topic_ros_name(topic: Any) -> str:
    """The ROS name a topic is published under; ``/Name`` when the model leaves it open."""
    return topic.rosName or f"/{topic.name}"


def _endpoint_caller_of(stand_in: Any, system: Any) -> Any | None:
    """The endpoint client that forwards calls arriving at an endpoint stand-in server."""
    for connection in system.connections:
        if connection.source is stand_in and isinstance(connection.target, tsm().ServiceClient):
            return connection.target
    return None


def server_ros_name(server: Any, system: Any) -> str:
    """The ROS name under which ``server`` is offered in its container.

    An endpoint stand-in without a name of its own offers the service under the name
    of the real server it forwards to, so a client calling it keeps working unchanged
    after a migration. A server with no name at all advertises its interface name,
    relative to the container namespace.
    """
    seen: set[int] = set()
    current = server
    while current is not None and id(current) not in seen:
        seen.add(id(current))
        if current.rosName:
            return current.rosName
        if not isinstance(current.eContainer(), tsm().Endpoint):
            return current.name
        caller = _endpoint_caller_of(current, system)
        current = caller.server if caller is not None else None
    return server.name


def remappings(node: Any, system: Any) -> list[tuple[str, str]]:
    """``(interface name, ROS name)`` for every connected interface, in model order."""
    T = tsm()
    rules = []
    for interface in node.interfaces:
        if isinstance(interface, T.Publisher | T.Subscriber):
            if interface.topic is not None:
                rules.append((interface.name, topic_ros_name(interface.topic)))
        elif isinstance(interface, T.ServiceServer):
            if interface.rosName:
                rules.append((interface.name, interface.rosName))
        elif isinstance(interface, T.ServiceClient) and interface.server is not None:
            rules.append((interface.name, server_ros_name(interface.server, system)))
    return rules


def require_implementation(node: Any) -> tuple[str, str]:
    """The node's ``(package, executable)``; the resolver guarantees both are set."""
    if not node.package or not node.executable:
        container = node.eContainer()
        raise ValueError(
            f"node {container.name}.{node.name} has no implementation (package/executable); "
            "the resolved product must bind one"
        )
    return node.package, node.executable


def checked_value(parameter: Any) -> str:
    """The canonical text of a parameter, refused when it does not fit its type.

    The parsers check values already; checking again here keeps a hand-built or
    corrupted model from producing a launch file that fails only on the robot.
    """
    kind, text = parameter.type.name, parameter.value
    where = f"parameter {parameter.eContainer().name}.{parameter.name}"
    try:
        if kind == "int":
            int(text, 10)
        elif kind == "double" and not math.isfinite(float(text)):
            raise ValueError("not a finite number")
        elif kind == "bool" and text not in BOOL_TEXT:
            raise ValueError("expected true or false")
        elif kind == "yaml":
            yaml.safe_load(text)
    except (ValueError, yaml.YAMLError) as error:
        raise ValueError(f"{where}: {text!r} is not a valid {kind} value ({error})") from None
    return text


def header_text(product: ResolvedProduct, container: Any) -> str:
    """The provenance comment; no timestamp so the same product gives the same bytes."""
    name = re.sub(r"[^A-Za-z0-9_.]", "_", product.name)
    return (
        f" Generated by spl-robotics {__version__} for product {name}, "
        f"container {container.name}. Edit the models, not this file. "
    )


def _plain(text: str, what: str) -> str:
    if "$" in text:
        raise ValueError(f"{what} {text!r} contains '$', which roslaunch would substitute")
    return text


def _parameter_element(node_element: Any, parameter: Any) -> None:
    if parameter.value is None:
        node_element.append(
            etree.Comment(f" parameter {parameter.name}: left to the node's default ")
        )
        return
    text = checked_value(parameter)
    kind = parameter.type.name
    if kind == "yaml" or (kind == "string" and ("$" in text or text != text.strip())):
        # roslaunch substitutes and strip()s <param value>; rosparam text is YAML, taken
        # as written (subst_value defaults to false).
        element = etree.SubElement(node_element, "rosparam", param=parameter.name)
        element.text = text if kind == "yaml" else json.dumps(text, ensure_ascii=False)
        return
    etree.SubElement(node_element, "param", name=parameter.name, value=text, type=ROS1_TYPES[kind])


def launch_document(product: ResolvedProduct, container: Any) -> etree._Element:
    """The ``<launch>`` tree of one container: its nodes, never its endpoint."""
    root = etree.Element("launch")
    root.append(etree.Comment(header_text(product, container)))
    system = product.system
    for node in container.nodes:
        if node.eClass.name in ("Writer", "Reader"):
            # generated data clients are rclpy (ROS 2) packages: roslaunch cannot start them
            root.append(etree.Comment(f" {node.name}: ROS 2 data client, see ros2/ "))
            continue
        package, executable = require_implementation(node)
        element = etree.SubElement(root, "node")
        element.set("pkg", _plain(package, "package"))
        element.set("type", _plain(executable, "executable"))
        element.set("name", _plain(node.name, "node name"))
        if container.namespace:
            element.set("ns", _plain(container.namespace, "namespace"))
        if node.args:
            element.set("args", _plain(node.args, "node arguments"))
        for parameter in node.parameters:
            _parameter_element(element, parameter)
        for source, target in remappings(node, system):
            etree.SubElement(
                element,
                "remap",
                {"from": _plain(source, "interface"), "to": _plain(target, "ROS name")},
            )
    return root


def serialize(root: etree._Element) -> bytes:
    """UTF-8 with declaration, two-space indentation and a final newline."""
    etree.indent(root, space="  ")
    data = etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True)
    return data if data.endswith(b"\n") else data + b"\n"


def launch_file(product: ResolvedProduct, container: Any) -> bytes:
    return serialize(launch_document(product, container))


def generate(product: ResolvedProduct) -> dict[str, bytes]:
    """``ros1/<container>.launch`` for every robot and cloud container."""
    return {
        f"ros1/{container.name}.launch": launch_file(product, container)
        for container in product.system.containers
    }
