"""From the loaded combinations to a product line: features, optional nodes, parameters.

The rules are docs/import.md's ("How the line is found"): an argument becomes a feature
(an alternative group of its values, or an optional feature for a ``true``/``false``
switch); a node present in every combination is mandatory, one present in some is
optional and required by the features that bring it; a parameter or an implementation
that differs between combinations is set by those features. What varies with one
argument is said by that argument's features; what varies with several together gets a
feature per combination, tied to them by a constraint (``burger_hector <=> burger and
hector``), so that every product still has exactly its combination's nodes.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

from spl.dsl import rosnames
from spl.importers.launch.reading import (
    Argument,
    Combination,
    ImportRefused,
    LoadedNode,
    Omission,
)
from spl.importers.launch.values import MISSING, NodeParameter, node_parameters
from spl.importers.naming import feature_name, is_name

T = TypeVar("T", bound=Hashable)


@dataclass(frozen=True)
class Condition:
    """``when FEATURE selected`` (or ``not selected``)."""

    feature: str
    selected: bool = True


@dataclass
class ImportedNode:
    container: str  # Robot, Cloud, Robot_<namespace>, ...
    namespace: str  # "" for the root namespace
    robot: bool
    name: str
    optional: bool
    implementation: tuple[str, str]
    args: str
    parameters: list[NodeParameter]
    source: str  # file:line of the <node>, relative to its package path folder
    file: str
    line: int


@dataclass
class Statements:
    requires: list[ImportedNode] = field(default_factory=list)
    # (node, (package, executable, args)): the command that runs it under the condition
    implementations: list[tuple[ImportedNode, tuple[str, str, str]]] = field(default_factory=list)
    parameters: list[tuple[ImportedNode, str, str]] = field(default_factory=list)  # literal


@dataclass
class ImportedLine:
    name: str
    arguments: list[Argument]
    features: dict[tuple[int, str], Condition | None]  # (argument, value) -> condition
    groups: dict[int, str]  # argument -> the feature of its group of values
    combination_features: dict[tuple[str, ...], str]
    nodes: list[ImportedNode]
    blocks: dict[Condition, Statements]
    products: list[tuple[str, tuple[str, ...], list[str]]]  # name, values, features
    warnings: list[Omission]


class Split:
    """How a value over combinations is decided: by nothing, one argument, or jointly.

    For an optional node (``everywhere`` given: every combination, while ``values``
    holds those with the node) an argument decides only if each of its values it is
    used for brings the node: a statement on a node keeps it (docs/semantics.md), so a
    parameter set under ``waffle`` would keep a node ``hector`` alone brings."""

    def __init__(
        self,
        arguments: Sequence[Argument],
        values: dict[tuple[str, ...], T],
        everywhere: Sequence[tuple[str, ...]] = (),
    ) -> None:
        self.constant = len(set(values.values())) == 1
        self.argument: int | None = None
        self.by_value: dict[str, T] = {}
        if not self.constant:
            for index, _ in enumerate(arguments):
                by_value: dict[str, T] = {}
                if not all(by_value.setdefault(c[index], v) == v for c, v in values.items()):
                    continue
                if all(c in values for c in everywhere if c[index] in by_value):
                    self.argument, self.by_value = index, by_value
                    break
        self.joint = values


def build_line(
    name: str,
    arguments: list[Argument],
    combinations: list[Combination],
    warnings: list[Omission],
    is_robot: Callable[[LoadedNode], bool],
) -> ImportedLine:
    features, groups = _argument_features(arguments, name)
    line = ImportedLine(
        name=name, arguments=arguments, features=features, groups=groups,
        combination_features={}, nodes=[], blocks={}, products=[], warnings=list(warnings),
    )  # fmt: skip
    everywhere = [c.values for c in combinations]
    appearances: dict[str, dict[tuple[str, ...], LoadedNode]] = {}
    for combination in combinations:
        for node in combination.nodes:
            appearances.setdefault(node.ros_name, {})[combination.values] = node
    by_combination = {c.values: c for c in combinations}
    for ros_name, seen in appearances.items():
        first = next(iter(seen.values()))
        problem = _problem_of(first, [n for n in seen.values()])
        if problem:
            line.warnings.append(
                Omission(first.file, first.line, f"node {ros_name} left out: {problem}")
            )
            continue
        robot = is_robot(first)
        namespace = first.namespace.strip("/")
        container = ("Robot" if robot else "Cloud") + (
            "_" + namespace.replace("/", "_") if namespace else ""
        )
        presence = Split(arguments, {c: c in seen for c in everywhere})
        within = everywhere if not presence.constant else ()
        # what runs the node, with its arguments: an .rm implementation statement sets both
        commands = {
            c: (n.package, n.executable, _writable_args(n, line.warnings)) for c, n in seen.items()
        }
        args_text = commands[next(iter(seen))][2]  # the first combination's, the .tsm's
        implementation = Split(arguments, commands, within)
        parameters, left_out = node_parameters(ros_name, {c: by_combination[c] for c in seen})
        line.warnings.extend(left_out)
        imported = ImportedNode(
            container=container, namespace=namespace, robot=robot, name=first.name,
            optional=not presence.constant, implementation=(first.package, first.executable),
            args=args_text, parameters=parameters, source=f"{first.source}:{first.line}",
            file=first.file, line=first.line,
        )  # fmt: skip
        line.nodes.append(imported)
        if not presence.constant:
            for condition in _conditions(line, presence, lambda present: bool(present)):
                line.blocks.setdefault(condition, Statements()).requires.append(imported)
        if not implementation.constant:
            command = (*imported.implementation, args_text)
            for condition, value in _valued(line, implementation, command):
                line.blocks.setdefault(condition, Statements()).implementations.append(
                    (imported, value)
                )
        for parameter in parameters:
            split = Split(arguments, parameter.literals, within)
            if split.constant:
                continue
            for condition, value in _valued(line, split, MISSING):
                line.blocks.setdefault(condition, Statements()).parameters.append(
                    (imported, parameter.name, value)
                )
    _unplaced_parameters(line, combinations)
    for values in everywhere:
        chosen = [
            c.feature
            for i, v in enumerate(values)
            if (c := line.features[(i, v)]) is not None and c.selected
        ]
        if values in line.combination_features:
            chosen.append(line.combination_features[values])
        chosen = chosen or [name]  # a product selects a feature: the root, when no other
        varying = [v for a, v in zip(arguments, values, strict=True) if len(a.values) > 1]
        line.products.append(("_".join(varying) or name, values, chosen))
    line.warnings.sort(key=lambda w: (w.file, w.line, w.message))
    named: dict[str, tuple[str, ...]] = {}
    for product, values, _ in line.products:
        if named.setdefault(product, values) != values:
            raise ImportRefused(
                f"the combinations {' '.join(named[product])} and {' '.join(values)} would "
                f"both be the product {product} (values joined with _)"
            )
    return line


def _problem_of(first: LoadedNode, appearances: list[LoadedNode]) -> str | None:
    """Why a node cannot be written in a .tsm (docs/tsm.md, "Names and safety"), if so."""
    if not is_name(first.name):
        return "its name is not an identifier, or a word of spl's languages"
    for node in appearances:
        problem = rosnames.problem_package(node.package) or rosnames.problem_executable(
            node.executable
        )
        if problem:
            return problem
    return None


def _writable_args(node: LoadedNode, warnings: list[Omission]) -> str:
    """The node's command line as a .tsm or .rm ``args`` string; empty, with a located
    warning, when it cannot be one."""
    text = _args_text(node)
    problem = _args_problem(node, text)
    if problem is None:
        return text
    warning = Omission(node.file, node.line, (
        f"node {node.ros_name}: args {text[:80]!r} left out: {problem}"))  # fmt: skip
    if warning not in warnings:
        warnings.append(warning)
    return ""


def _args_problem(node: LoadedNode, text: str) -> str | None:
    """Why the node's command line cannot be a .tsm ``args`` string, if so: the string
    is split at blanks, so an argument holding one (``'a b'``) would become two."""
    if any(not token or any(c.isspace() for c in token) for token in node.args):
        return "an argument holds blanks, which a .tsm args string cannot quote"
    return rosnames.problem_args(text) if text else None


def _args_text(node: LoadedNode) -> str:
    """The node's arguments and remappings, as roslaunch passes them to its process."""
    return " ".join([*node.args, *(f"{source}:={target}" for source, target in node.remaps)])


def _conditions(line: ImportedLine, split: Split, wanted: Any) -> list[Condition]:
    """The conditions under which ``wanted(value)`` holds, one per feature."""
    if split.argument is not None:
        return [
            c
            for value, v in split.by_value.items()
            if wanted(v) and (c := line.features[(split.argument, value)]) is not None
        ]
    return [_combination(line, values) for values, v in split.joint.items() if wanted(v)]


def _valued(line: ImportedLine, split: Split, default: object) -> list[tuple[Condition, Any]]:
    """``(condition, value)`` for every value that differs from ``default``."""
    if split.argument is not None:
        pairs = [((split.argument, k), v) for k, v in split.by_value.items()]
        return [
            (c, v) for key, v in pairs if v != default and (c := line.features[key]) is not None
        ]
    return [(_combination(line, c), v) for c, v in split.joint.items() if v != default]


def _combination(line: ImportedLine, values: tuple[str, ...]) -> Condition:
    taken = {c.feature for c in line.features.values() if c is not None} | {line.name}
    if values not in line.combination_features:
        name = "_".join(values)
        while name in taken or name in line.combination_features.values():
            name += "_combination"
        line.combination_features[values] = name
    return Condition(line.combination_features[values])


def _argument_features(
    arguments: list[Argument], root: str
) -> tuple[dict[tuple[int, str], Condition | None], dict[int, str]]:
    """The condition of every argument value, and the feature of every group argument."""
    features: dict[tuple[int, str], Condition | None] = {}
    groups: dict[int, str] = {}
    taken = {root}
    for index, argument in enumerate(arguments):
        if len(argument.values) == 1:
            features[(index, argument.values[0])] = None  # a fixed value: no feature
            continue
        if argument.is_switch:
            name = feature_name(argument.name, taken, f"{argument.name}_arg")
            taken.add(name)
            for value in argument.values:
                features[(index, value)] = Condition(name, value.lower() == "true")
            continue
        group = feature_name(argument.name, taken, f"{argument.name}_arg")
        taken.add(group)
        groups[index] = group
        for value in argument.values:
            name = feature_name(value, taken, f"{argument.name}_{value}")
            taken.add(name)
            features[(index, value)] = Condition(name)
    return features, groups


def _unplaced_parameters(
    line: ImportedLine,
    combinations: list[Combination],
) -> None:
    """A parameter outside every node's private namespace has no place in a .tsm."""
    seen: set[str] = set()
    for combination in combinations:
        prefixes = tuple(f"{n.ros_name}/" for n in combination.nodes)
        for key in combination.params:
            if key in seen or key.startswith(prefixes):
                continue
            seen.add(key)
            file, number = combination.param_places.get(key, ("", 0))
            line.warnings.append(Omission(file, number, (
                f"parameter {key} left out: it is private to no node the launch files "
                "start, and a .tsm parameter belongs to a node")))  # fmt: skip
