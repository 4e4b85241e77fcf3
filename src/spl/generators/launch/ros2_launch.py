"""ROS 2 launch XML for a container's nodes: the ros2 target writes one per container,
the Kubernetes target mounts one per cloud instance, a fleet one per private instance.

Same nodes, parameters and remappings as the ROS 1 files (the rules live in
:mod:`spl.resolver.architecture.ros_names` and :mod:`spl.generators.launch.launch_xml`), in the ROS
2 XML
frontend's vocabulary (``exec``, ``namespace``, typed ``param``). The ROS 2 frontend
expands ``$(...)`` substitutions in every attribute but, unlike roslaunch, lets a
backslash escape ``$``, quotes and itself; every attribute value is escaped that way,
so model text reaches the node exactly as written.

Parameters carry the launch_ros ``type`` attribute (read since Galactic; Humble and
Jazzy have it): without it the frontend guesses the type from the text, and a string
parameter ``"0483"`` would reach the node as the integer 483. ROS 2 parameters have no
dictionary values, so a ``yaml`` mapping becomes nested ``<param>`` elements (the
node sees ``filters.median.window``), as ROS 2 parameter files do.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import TYPE_CHECKING

import yaml
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

__all__ = ["escape_substitutions", "launch_document", "launch_file"]

ROS2_TYPES = {"string": "str", "int": "int", "double": "float", "bool": "bool", "yaml": "yaml"}

_SPECIAL = re.compile(r"""([\\$'"])""")


def escape_substitutions(text: str) -> str:
    """Text the ROS 2 substitution grammar reads back as exactly ``text``. Most texts
    have nothing to escape: found by one search, without re.sub's template expansion
    (which Python does in Python for every call)."""
    return text if _SPECIAL.search(text) is None else _SPECIAL.sub(r"\\\1", text)


def _set(element: etree._Element, attribute: str, value: str) -> None:
    element.set(attribute, escape_substitutions(value))


def _yaml_text(value: object) -> str:
    text = yaml.safe_dump(value, default_flow_style=True, width=2**31, allow_unicode=True)
    return text.removesuffix("\n...\n").strip()


def _yaml_parameter(
    parent: etree._Element, name: str, value: object, parameter: tsm_types.Parameter
) -> None:
    """A yaml parameter: mappings become nested ``<param>`` (ROS 2 has no dict values)."""
    if value is None or value == {}:
        where = f"{parameter.eContainer().name}.{parameter.name}"
        raise ValueError(f"parameter {where}: ROS 2 parameters cannot be null or empty ({name})")
    param = etree.SubElement(parent, "param")
    _set(param, "name", name)
    if isinstance(value, dict):
        for key, item in value.items():
            _yaml_parameter(param, str(key), item, parameter)
        return
    _set(param, "value", _yaml_text(value))
    param.set("type", "yaml")


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
    chosen = list(container.nodes if nodes is None else nodes)
    for argument, default in data_client_arguments(product, chosen).items():
        arg = etree.SubElement(root, "arg")
        _set(arg, "name", argument)
        _set(arg, "default", default)
    for node in chosen:
        package, executable = require_implementation(node)
        element = etree.SubElement(root, "node")
        _set(element, "pkg", package)
        _set(element, "exec", executable)
        _set(element, "name", node.name)
        if container.namespace:
            _set(element, "namespace", container.namespace)
        if node.args:
            _set(element, "args", node.args)
        for parameter in node.parameters:
            if parameter.value is None:
                element.append(
                    etree.Comment(f" parameter {parameter.name}: left to the node's default ")
                )
                continue
            text = checked_value(parameter)
            if parameter.type.name == "yaml":
                _yaml_parameter(element, parameter.name, yaml.safe_load(text), parameter)
                continue
            param = etree.SubElement(element, "param")
            _set(param, "name", parameter.name)
            _set(param, "value", text)
            param.set("type", ROS2_TYPES[parameter.type.name])
        client = data_client_launch(product, node)
        if client is not None:  # a generated writer or reader (clients/ros2/<package>)
            param = etree.SubElement(element, "param", name="store_url")
            param.set("value", f"$(var {client.argument})")
            for name, value, kind in client.parameters:
                param = etree.SubElement(element, "param")
                _set(param, "name", name)
                _set(param, "value", value)
                param.set("type", ROS2_TYPES[kind])
        for source, target in remappings(node, product.system):
            remap = etree.SubElement(element, "remap")
            _set(remap, "from", source)
            _set(remap, "to", target)
    return root


def launch_file(
    product: ResolvedProduct,
    container: tsm_types.Container,
    nodes: Iterable[tsm_types.Node] | None = None,
    header: str | None = None,
) -> bytes:
    return serialize(launch_document(product, container, nodes, header))
