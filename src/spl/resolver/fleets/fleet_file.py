"""The fleet file: several robots deployed from one product line, sharing cloud nodes.

::

    fleet: lab
    product_line: ../product_lines/mapping3d     # relative to this file
    robots:
      youbot_1: {group: lab, features: [YouBot, Stereo, Room]}
      youbot_2: {group: lab, features: [YouBot, Depth, Room], sharing: {SharedMap: protected}}
      roomba_1: {group: hall, capabilities: roomba.yaml, features: [Corridor]}

A robot entry takes every key of a product selection (``features``, ``deselected``,
``sharing``, ``attributes``, ``deployment``, ``capabilities``) plus ``group``, the
group whose ``protected`` cloud instances the robot shares (default ``default``). The
robot's name is its Rapyuta robotID unless ``deployment`` gives one. Like every input,
the file is read with located errors (``file:line:col``), all of them at once.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

import yaml

from spl.core.diagnostics import DiagnosticSink, Location
from spl.resolver.resolution.located_yaml import read_yaml
from spl.resolver.resolution.product_selection import ProductSelection, read_selection

FLEET_KEYS = ("fleet", "product_line", "robots")
NAME = re.compile(r"[A-Za-z][A-Za-z0-9_-]{0,63}")  # a Rapyuta tag and a robotID
NAME_RULE = "a letter, then up to 63 letters, digits, '_' or '-'"
DEFAULT_GROUP = "default"


@dataclass
class FleetRobot:
    name: str
    selection: ProductSelection  # named after the robot; located in the fleet file
    group: str = DEFAULT_GROUP
    location: Location | None = None  # of the robot's name in the fleet file


@dataclass
class Fleet:
    name: str
    source: str  # the fleet file
    product_line: Path
    robots: list[FleetRobot] = field(default_factory=list)
    product_line_location: Location | None = None

    def robot(self, name: str) -> FleetRobot | None:
        return next((r for r in self.robots if r.name == name), None)


def load_fleet(path: str | Path) -> Fleet:
    """Read a fleet file; raise ModelError with every problem, located."""
    path = Path(path)
    filename = str(path)
    sink = DiagnosticSink()
    root, at = read_yaml(path, sink)
    fleet = Fleet(path.stem, filename, path.parent)
    if not isinstance(root, yaml.MappingNode):
        sink.error(
            Location(filename, 1, 1), "a fleet file is a mapping (fleet, product_line, robots)"
        )
        sink.raise_if_errors()
    root = cast("yaml.MappingNode", root)  # (else raised above)
    given: dict[str, yaml.Node] = {}
    for key_node, value_node in root.value:
        key = key_node.value
        if key not in FLEET_KEYS:
            sink.error(at(key_node), f"unknown key {key!r} (expected {', '.join(FLEET_KEYS)})")
        elif key in given:
            sink.error(at(key_node), f"{key} given twice")
        else:
            given[key] = value_node
    name = given.get("fleet")
    if name is not None:
        if isinstance(name, yaml.ScalarNode) and NAME.fullmatch(name.value):
            fleet.name = name.value
        else:
            sink.error(at(name), f"fleet: expected a name ({NAME_RULE})")
    line = given.get("product_line")
    if line is None:
        sink.error(Location(filename, 1, 1), "no product_line: the folder of the product line")
    elif not isinstance(line, yaml.ScalarNode) or not line.value:
        sink.error(at(line), "product_line: expected a folder, relative to this file")
    else:
        fleet.product_line = Path(os.path.normpath(path.parent / line.value))
        fleet.product_line_location = at(line)
        if not fleet.product_line.is_dir():
            sink.error(at(line), f"product_line: no such folder {line.value}")
    robots = given.get("robots")
    if not isinstance(robots, yaml.MappingNode) or not robots.value:
        where = at(robots) if robots is not None else Location(filename, 1, 1)
        sink.error(where, "robots: expected NAME: {group: ..., features: [...]} for each robot")
    else:
        for name_node, entry in robots.value:
            robot = _robot(name_node, entry, at, sink, filename)
            if robot is None:
                continue
            if fleet.robot(robot.name) is not None:
                sink.error(robot.location, f"robot {robot.name} is listed twice")
                continue
            fleet.robots.append(robot)
    sink.raise_if_errors()
    return fleet


def _robot(name_node, entry, at, sink: DiagnosticSink, filename: str) -> FleetRobot | None:
    name = name_node.value if isinstance(name_node, yaml.ScalarNode) else None
    if name is None or not NAME.fullmatch(name):
        sink.error(at(name_node), f"robot name {name!r}: expected {NAME_RULE} (a robotID)")
        return None
    if not isinstance(entry, yaml.MappingNode):
        sink.error(at(entry), f"robot {name}: expected {{group: ..., features: [...]}}")
        return None
    selection = ProductSelection(name=name, features=[], source=filename)
    robot = FleetRobot(name, selection, location=at(name_node))
    for key_node, value_node in read_selection(entry.value, at, sink, selection, ("group",)):
        if isinstance(value_node, yaml.ScalarNode) and NAME.fullmatch(value_node.value):
            robot.group = value_node.value
        else:
            sink.error(at(value_node), f"{key_node.value}: expected a group name ({NAME_RULE})")
    if not selection.features and "capabilities" not in selection.locations:
        sink.error(robot.location, f"robot {name}: no features selected (features or capabilities)")
    return robot
