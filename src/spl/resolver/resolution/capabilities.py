"""Feature selection from a robot's capabilities (docs/fleets.md, "Capability-driven
selection"; the mapping paper's section VII, docs/index.md).

A robot capability file describes what a robot *is* (YAML, every key a capability;
nested mappings are reached with dotted names)::

    base: youbot
    sensors: [stereo_camera, bumper]
    onboard_pc: true
    compute: {cores: 4}

The feature model maps capabilities to features with ``capability`` conditions (see
``src/spl/dsl/fm/capability.tx``). For a robot, a feature whose conditions all hold is selected; a
feature with a condition the file contradicts is deselected; a feature whose condition
names a capability the file does not declare is left to the rest of the selection.
The SAT completion then finishes the selection as for any other. Every choice keeps the
capability and the condition that made it, so ``spl resolve`` can say which capability
chose which feature, and a selection that contradicts the robot is refused naming both.
"""

from __future__ import annotations

import datetime
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, cast

import yaml

from spl.core.diagnostics import Diagnostic, DiagnosticSink, Location, ModelError, location_of
from spl.dsl.fm.language import all_features
from spl.dsl.fm.printer import format_capability
from spl.resolver.resolution.located_yaml import read_yaml

KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
YAML_SET = "tag:yaml.org,2002:set"
Scalar = str | int | float | bool
Capability = Scalar | list[Scalar]  # a capability's value in a robot's file

if TYPE_CHECKING:
    from spl.metamodels import fm_types


@dataclass
class RobotCapabilities:
    """The capabilities of one robot: dotted name -> scalar or list of scalars."""

    source: str
    values: dict[str, Capability] = field(default_factory=dict)
    locations: dict[str, Location] = field(default_factory=dict)

    @property
    def name(self) -> str:
        return Path(self.source).stem


@dataclass(frozen=True)
class CapabilityChoice:
    """A feature selected or deselected because of one of the robot's capabilities."""

    feature: str
    selected: bool
    condition: str  # as the .fm writes it: base = "youbot"
    key: str  # the capability deciding
    value: Capability  # its value in the robot's file
    where: Location  # of the capability in the robot's file
    rule: Location | None  # of the condition in the feature model

    def __str__(self) -> str:
        verb = "selects" if self.selected else "deselects"
        holds = "holds" if self.selected else "does not hold"
        return (
            f"capability {self.key}: {_shown(self.value)} ({self.where}) {verb} {self.feature}: "
            f"{self.condition} {holds} ({self.rule})"
        )


def load_capabilities(path: str | Path) -> RobotCapabilities:
    """Read a robot capability file; every problem is located in the YAML."""

    path = Path(path)
    sink = DiagnosticSink()
    root, at = read_yaml(path, sink)
    capabilities = RobotCapabilities(str(path))
    if not isinstance(root, yaml.MappingNode):
        sink.error(Location(str(path), 1, 1), "a capability file is a mapping: NAME: VALUE")
        sink.raise_if_errors()

    def read(node: yaml.MappingNode, prefix: str) -> None:
        for key_node, value_node in node.value:
            if not isinstance(key_node, yaml.ScalarNode):  # `? [a, b]`: no node text in messages
                sink.error(at(key_node), f"capability name: a {key_node.id} is not an identifier")
                continue
            key = key_node.value
            if not KEY.fullmatch(key):
                sink.error(at(key_node), f"capability name {key!r} is not an identifier")
                continue
            name = f"{prefix}{key}"
            if name in capabilities.locations:
                sink.error(at(key_node), f"capability {name} given twice")
                continue
            capabilities.locations[name] = at(key_node)
            expected = f"capability {name}: expected a string, number, true/false or a list of them"
            if isinstance(value_node, yaml.MappingNode) and value_node.tag == YAML_SET:
                # read as a mapping it would report each member's missing value
                message = f"capability {name}: a set (!!set) is not a list; write it as [A, B]"
                sink.error(at(value_node), message)
                continue
            if isinstance(value_node, yaml.MappingNode):
                read(value_node, f"{name}.")
                continue
            try:  # a tag safe YAML has no constructor for, a scalar its tag cannot convert
                value = yaml.safe_load(yaml.serialize(value_node))
            except yaml.YAMLError as exc:
                sink.error(at(value_node), f"{expected} ({getattr(exc, 'problem', None) or exc})")
                continue
            except (ValueError, TypeError) as exc:  # `!!int x`, `!!timestamp 2024-13-01`
                sink.error(at(value_node), f"{expected} ({exc})")
                continue
            items = value if isinstance(value, list) else [value]
            odd = [item for item in items if not _scalar(item)]
            if not items or odd:
                got = f" (got {_kind(odd[0])})" if odd else " (got an empty list)"
                sink.error(at(value_node), expected + got)
                continue
            capabilities.values[name] = cast("Capability", value)  # scalars, checked

    read(root, "")
    sink.raise_if_errors()
    return capabilities


def _kind(value: object) -> str:
    """What a capability's value is instead of a scalar, in the YAML's words."""
    if isinstance(value, datetime.date):  # (datetimes too) an unquoted 2024-01-01
        return "a date or time: quote it to give a string"
    if isinstance(value, float):
        return "an infinite or not-a-number value"
    return _KINDS.get(type(value), "a value of another kind")


_KINDS: dict[type, str] = {
    type(None): "an empty value",
    bytes: "binary data",
    dict: "a mapping",
    list: "a list in the list",
}


def _scalar(value: object) -> bool:
    if isinstance(value, float):
        return value == value and value not in (float("inf"), float("-inf"))
    return isinstance(value, Scalar) and value is not None


def _shown(value: object) -> str:
    return (
        yaml.safe_dump(value, default_flow_style=True, width=2**31).removesuffix("\n...\n").strip()
    )


def choose_features(
    fm: fm_types.FeatureModel, capabilities: RobotCapabilities
) -> list[CapabilityChoice]:
    """The features the robot's capabilities select or deselect, in tree order; a
    condition comparing a capability with a value of another kind is a located error."""
    sink = DiagnosticSink()
    choices = []
    for feature in all_features(fm):
        if not feature.capabilities:
            continue
        results = [(c, _holds(c, capabilities, sink)) for c in feature.capabilities]
        failed = next(((c, r) for c, r in results if r is False), None)
        if failed is not None:
            choices.append(_choice(feature, False, failed[0], capabilities))
        elif all(r is True for _, r in results):
            choices.extend(_choice(feature, True, c, capabilities) for c, _ in results)
    sink.raise_if_errors()
    return choices


def _choice(
    feature: fm_types.Feature,
    selected: bool,
    condition: fm_types.CapabilityCondition,
    capabilities: RobotCapabilities,
) -> CapabilityChoice:
    return CapabilityChoice(
        feature.name,
        selected,
        format_capability(condition),
        condition.key,
        capabilities.values[condition.key],
        capabilities.locations[condition.key],
        location_of(condition),
    )


def _holds(
    condition: fm_types.CapabilityCondition, capabilities: RobotCapabilities, sink: DiagnosticSink
) -> bool | None:
    """True or False, or None when the robot does not declare the capability."""
    key = condition.key
    if key not in capabilities.values:
        return None
    value = capabilities.values[key]
    operator = condition.operator

    def mismatch(expected: str) -> None:
        if any(d.location == capabilities.locations[key] for d in sink.diagnostics):
            return  # one report per capability: the first condition testing it
        sink.error(
            capabilities.locations[key],
            f"capability {key} is {_shown(value)}, but the feature model tests "
            f"'{format_capability(condition)}' ({location_of(condition)}): expected {expected}",
        )

    if not operator:
        if not isinstance(value, bool):
            mismatch("true or false")
            return None
        return value
    literal = _literal(condition)
    if operator == "has":
        items = value if isinstance(value, list) else [value]
        return any(_same_kind(item, literal) and item == literal for item in items)
    if isinstance(value, list):
        mismatch("a single value, not a list")
        return None
    if not _same_kind(value, literal):
        mismatch(f"a {condition.valueType.name}")
        return None
    if operator == "=":
        return value == literal
    if operator == "!=":
        return value != literal
    # values of one kind (numbers, or strings) compare
    ordered, bound = cast("float", value), cast("float", literal)
    return ordered >= bound if operator == ">=" else ordered <= bound


def _literal(condition: fm_types.CapabilityCondition) -> Scalar:
    kind, text = condition.valueType.name, condition.value
    if kind == "bool":
        return text == "true"
    if kind == "int":
        return int(text)
    if kind == "double":
        return float(text)
    return text


def _same_kind(value: object, literal: Scalar) -> bool:
    if isinstance(literal, bool) or isinstance(value, bool):
        return isinstance(literal, bool) and isinstance(value, bool)
    if isinstance(literal, int | float):
        return isinstance(value, int | float)
    return isinstance(value, str)


def merge_choices(
    choices: list[CapabilityChoice],
    selected: list[str],
    deselected: list[str],
    locations: dict[str, Location],
    source: Location,
) -> tuple[list[str], list[str], dict[str, Location]]:
    """The selection with the capabilities' choices added; a feature the user selects
    but the robot's capabilities deselect (or the other way round) is an error naming
    both places (``source`` locates features given without a location of their own)."""
    selected, deselected, locations = list(selected), list(deselected), dict(locations)
    problems = []
    for choice in choices:
        same, other = (selected, deselected) if choice.selected else (deselected, selected)
        if choice.feature in other:
            verb = "deselected" if choice.selected else "selected"
            problems.append(
                Diagnostic(
                    locations.get(choice.feature, source),
                    f"feature {choice.feature} is {verb}, but the robot's capabilities decide "
                    f"otherwise: {choice}",
                )
            )
        elif choice.feature not in same:
            same.append(choice.feature)
            locations.setdefault(choice.feature, choice.where)
    if problems:
        raise ModelError(problems)
    return selected, deselected, locations
