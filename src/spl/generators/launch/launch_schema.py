"""Validation of generated launch files against the XSDs the project ships.

The schemas in ``generators/schemas/`` were written from the roslaunch and ROS 2 launch
XML documentation, so a launch file that passes them uses only tags and attributes
those tools know, with the values they check before any substitution. ``spl validate``
and the tests call these functions; the messages name line and column so a CI log
points at the offending tag.
"""

from __future__ import annotations

from functools import cache
from importlib.resources import files

from lxml import etree

__all__ = ["schema", "validate_ros1_launch", "validate_ros2_launch"]

SCHEMAS = {"ros1": "roslaunch.xsd", "ros2": "ros2launch.xsd"}


@cache
def schema(kind: str) -> etree.XMLSchema:
    """The compiled XSD for ``kind`` (``ros1`` or ``ros2``), loaded once per process."""
    source = files("spl.generators").joinpath("schemas", SCHEMAS[kind]).read_bytes()
    return etree.XMLSchema(etree.fromstring(source))


def _validate(kind: str, document: bytes) -> list[str]:
    # No entity expansion and no network: the file under test is untrusted input.
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    try:
        root = etree.fromstring(document, parser)
    except etree.XMLSyntaxError as error:
        return [f"{error.lineno}:{error.position[1]}: not well-formed XML: {error.msg}"]
    problems = []
    if root.tag != "launch":
        problems.append(f"{root.sourceline}:0: root element is <{root.tag}>, expected <launch>")
    checker = schema(kind)
    if not checker.validate(root):
        problems.extend(f"{e.line}:{e.column}: {e.message}" for e in checker.error_log)
    return problems


def validate_ros1_launch(document: bytes) -> list[str]:
    """Problems (``line:col: message``) of a roslaunch file; empty when it is valid."""
    return _validate("ros1", document)


def validate_ros2_launch(document: bytes) -> list[str]:
    """Problems (``line:col: message``) of a ROS 2 launch XML file; empty when it is valid."""
    return _validate("ros2", document)
