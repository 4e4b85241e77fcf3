"""ROS 1 launch files: one roslaunch XML file per container of a resolved product.

The XML is built as an lxml tree, never by string concatenation, so no model text can
add markup. Escaping XML is not enough for roslaunch, though: it expands ``$(...)``
substitution args in every attribute (``$(eval ...)`` runs Python) and has no escape
for ``$``; it also strips ``<param value>``. A string parameter value containing ``$``
or surrounding blanks is therefore written as a ``<rosparam>`` whose YAML text
roslaunch takes as written, and any other attribute that would carry a ``$`` is
refused.

The remapping rules (which ROS name every connected interface is bound to) are
:mod:`spl.resolver.architecture.ros_names`'s and what both launch flavours write alike is
:mod:`spl.generators.launch.launch_xml`'s, so the ROS 1 and ROS 2 files of one product agree.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from typing import TYPE_CHECKING

from lxml import etree

from spl.generators.launch.launch_xml import (
    checked_value,
    data_client_arguments,
    data_client_launch,
    header_text,
    require_implementation,
    serialize,
)
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.ros_names import remappings

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

__all__ = ["generate", "launch_document", "launch_file"]

ROS1_TYPES = {"string": "str", "int": "int", "double": "double", "bool": "bool", "yaml": "yaml"}


def _plain(text: str, what: str) -> str:
    if "$" in text:
        raise ValueError(f"{what} {text!r} contains '$', which roslaunch would substitute")
    return text


def _parameter_element(node_element: etree._Element, parameter: tsm_types.Parameter) -> None:
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


def launch_document(
    product: ResolvedProduct,
    container: tsm_types.Container,
    nodes: Iterable[tsm_types.Node] | None = None,
    header: str | None = None,
) -> etree._Element:
    """The ``<launch>`` tree of one container: its nodes (or only ``nodes`` of it, as a
    fleet runs one sharing partition of a container), never its endpoint."""
    root = etree.Element("launch")
    root.append(etree.Comment(header or header_text(product, container)))
    system = product.system
    chosen = list(container.nodes if nodes is None else nodes)
    for argument, default in data_client_arguments(product, chosen).items():
        etree.SubElement(root, "arg", name=argument, default=_plain(default, "store URL"))
    for node in chosen:
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
        client = data_client_launch(product, node)
        if client is not None:  # a generated writer or reader (clients/ros1/<package>)
            etree.SubElement(element, "param", name="store_url", value=f"$(arg {client.argument})")
            for name, value, kind in client.parameters:
                etree.SubElement(
                    element, "param", name=name, value=_plain(value, name), type=ROS1_TYPES[kind]
                )
        for source, target in remappings(node, system, ros1=True):
            etree.SubElement(
                element,
                "remap",
                {"from": _plain(source, "interface"), "to": _plain(target, "ROS name")},
            )
    return root


def launch_file(
    product: ResolvedProduct,
    container: tsm_types.Container,
    nodes: Iterable[tsm_types.Node] | None = None,
    header: str | None = None,
) -> bytes:
    return serialize(launch_document(product, container, nodes, header))


def generate(product: ResolvedProduct) -> dict[str, bytes]:
    """``ros1/<container>.launch`` for every robot and cloud container."""
    return {
        f"ros1/{container.name}.launch": launch_file(product, container)
        for container in product.system.containers
    }
