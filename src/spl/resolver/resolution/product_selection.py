"""Product selections: the YAML file of docs/resolution.md ("Selections"), or
``--features A,B,C`` inline.

A selection is user input like any model, so it is validated with located errors:
the YAML is composed (not just loaded) to keep the line and column of every key, and
every name that will later reach a generated file is checked here.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, cast

import yaml

from spl.core.diagnostics import DiagnosticSink, Location, ModelError
from spl.dsl import literals
from spl.resolver.resolution.located_yaml import read_yaml

if TYPE_CHECKING:
    from spl.resolver.architecture.product import AttributeValue
    from spl.resolver.resolution.capabilities import RobotCapabilities

IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
ROBOT_ID = re.compile(r"[A-Za-z][A-Za-z0-9_-]{0,63}")
URL = re.compile(r"wss?://[A-Za-z0-9.-]+(:[0-9]{1,5})?(/[A-Za-z0-9._~/-]*)?")
SHARING_MODES = ("private", "protected", "public")
TOP_LEVEL_KEYS = (
    "product",
    "features",
    "deselected",
    "sharing",
    "attributes",
    "deployment",
    "capabilities",
)
DEPLOYMENT_KEYS = {"robot_id": ROBOT_ID, "url": URL}


@dataclass
class ProductSelection:
    name: str
    features: list[str]
    deselected: list[str] = field(default_factory=list)
    sharing: dict[str, str] = field(default_factory=dict)  # feature -> mode
    # "Feature.attr" -> value, as the file gives it (checked against its type by resolve)
    attributes: dict[str, object] = field(default_factory=dict)
    deployment: dict[str, dict[str, str]] = field(default_factory=dict)  # container -> settings
    capabilities: RobotCapabilities | None = None  # chooses features (resolver.capabilities)
    # where each name was given (feature name / "Feature.attr" / sharing feature), for errors
    locations: dict[str, Location] = field(default_factory=dict)
    source: str = "--features"

    def location(self, key: str) -> Location:
        return self.locations.get(key) or Location(self.source, 1, 1)


def selection_from_list(text: str, name: str | None = None) -> ProductSelection:
    """``--features YouBot,Stereo`` (commas and/or spaces)."""
    sink = DiagnosticSink()
    # a feature named twice is selected once: the product (and its name) is the same
    features = list(dict.fromkeys(f for f in re.split(r"[,\s]+", text.strip()) if f))
    where = Location("--features", 1, 1)
    for feature in features:
        if not IDENT.fullmatch(feature):
            sink.error(where, f"{feature!r} is not a feature name")
    if not features:
        sink.error(where, "no feature given")
    sink.raise_if_errors()
    return ProductSelection(name=name or "_".join(features), features=features)


def _refuse_duplicate_keys(
    pairs: list[tuple[yaml.Node, yaml.Node]], at: Callable, sink: DiagnosticSink
) -> None:
    """A key given twice in a selection's mapping or in any mapping inside it is an error:
    YAML loaders keep the last value (and features read key by key got both lists), so
    one of the two would be ignored unseen."""
    pending = [pairs]
    while pending:
        first: dict[str, yaml.Node] = {}
        for key_node, value_node in pending.pop():
            if isinstance(key_node, yaml.ScalarNode):
                earlier = first.setdefault(key_node.value, key_node)
                if earlier is not key_node:
                    line = earlier.start_mark.line + 1
                    sink.error(
                        at(key_node), f"duplicate key {key_node.value!r} (first at line {line})"
                    )
            if isinstance(value_node, yaml.MappingNode):
                pending.append(value_node.value)


def load_selection_file(
    path: str | Path, unsaved: Mapping[str, str] | None = None
) -> ProductSelection:
    """A product selection file (``unsaved``: an editor's texts standing in for files)."""
    path = Path(path)
    filename = str(path)
    sink = DiagnosticSink()
    root, at = read_yaml(path, sink, unsaved)
    selection = ProductSelection(name=path.stem, features=[], source=filename)
    if not isinstance(root, yaml.MappingNode):
        sink.error(Location(filename, 1, 1), "a product selection is a mapping (product, features)")
        sink.raise_if_errors()
    root = cast("yaml.MappingNode", root)  # (else raised above)
    for key_node, value_node in read_selection(root.value, at, sink, selection, ("product",)):
        if isinstance(value_node, yaml.ScalarNode) and IDENT.fullmatch(value_node.value):
            selection.name = value_node.value
        else:
            sink.error(at(value_node), f"{key_node.value}: expected an identifier")
    if not selection.features and "capabilities" not in selection.locations:
        sink.error(
            Location(filename, 1, 1), "no features selected (key 'features' or 'capabilities')"
        )
    sink.raise_if_errors()
    return selection


def read_selection(
    pairs: list[tuple[yaml.Node, yaml.Node]],
    at: Callable[[yaml.Node], Location],
    sink: DiagnosticSink,
    selection: ProductSelection,
    extra_keys: tuple[str, ...] = (),
) -> list[tuple[yaml.Node, yaml.Node]]:
    """Read the product-selection keys of a YAML mapping into ``selection`` (a product file,
    or a robot entry of a fleet file); return the pairs of ``extra_keys`` for the caller.
    Every other key is a located error naming the keys allowed."""
    allowed = tuple(k for k in TOP_LEVEL_KEYS if k != "product" or k in extra_keys)
    allowed += tuple(k for k in extra_keys if k not in TOP_LEVEL_KEYS)
    _refuse_duplicate_keys(pairs, at, sink)
    extra = []
    for key_node, value_node in pairs:
        key = _scalar(key_node)
        if key not in allowed:
            shown = repr(key) if key is not None else _kind(key_node)
            sink.error(at(key_node), f"unknown key {shown} (expected {', '.join(allowed)})")
        elif key in extra_keys:
            extra.append((key_node, value_node))
        elif key in ("features", "deselected"):
            names = _names(value_node, at, sink, key)
            getattr(selection, key).extend(names)
            for name, node in zip(names, value_node.value, strict=False):
                selection.locations.setdefault(name, at(node))
        elif key == "sharing":
            for k, v in _pairs(value_node, at, sink, key):
                if not IDENT.fullmatch(k.value):
                    sink.error(at(k), f"sharing: {k.value!r} is not a feature name")
                elif v.value not in SHARING_MODES:
                    sink.error(at(v), f"sharing: expected one of {', '.join(SHARING_MODES)}")
                else:
                    selection.sharing[k.value] = v.value
                    selection.locations[f"sharing:{k.value}"] = at(k)
        elif key == "attributes":
            for k, v in _pairs(value_node, at, sink, key):
                if not re.fullmatch(r"[A-Za-z_]\w*\.[A-Za-z_]\w*", k.value, re.ASCII):
                    sink.error(at(k), f"attributes: {k.value!r} is not FEATURE.ATTRIBUTE")
                    continue
                value, problem = _value(yaml.serialize(v))
                if problem:
                    sink.error(at(v), f"attributes: {k.value}: {problem}")
                else:
                    selection.attributes[k.value] = value
                    selection.locations[k.value] = at(k)
        elif key == "capabilities":
            _capabilities(value_node, at, sink, selection)
        else:
            _deployment(value_node, at, sink, selection)
    return extra


def _capabilities(node, at, sink, selection: ProductSelection) -> None:
    """``capabilities: FILE``, a robot capability file relative to the file naming it."""
    from spl.resolver.resolution.capabilities import load_capabilities

    selection.locations["capabilities"] = at(node)
    if not isinstance(node, yaml.ScalarNode) or not node.value:
        sink.error(at(node), "capabilities: expected the path of a robot capability file")
        return
    where = at(node)
    path = Path(where.file).parent / node.value
    if not path.is_file():
        sink.error(where, f"capabilities: no such file {node.value}")
        return
    try:
        selection.capabilities = load_capabilities(path)
    except ModelError as exc:
        sink.diagnostics.extend(exc.diagnostics)


def _names(node, at, sink, key) -> list[str]:
    if not isinstance(node, yaml.SequenceNode):
        sink.error(at(node), f"{key}: expected a list of feature names")
        return []
    names = []
    for item in node.value:
        name = _scalar(item)
        if name is not None and IDENT.fullmatch(name):
            names.append(name)
        else:
            shown = repr(name) if name is not None else _kind(item)
            sink.error(at(item), f"{key}: {shown} is not a feature name")
    return names


def _pairs(node, at, sink, key):
    if not isinstance(node, yaml.MappingNode):
        sink.error(at(node), f"{key}: expected a mapping")
        return []
    pairs = []
    for k, v in node.value:
        if _scalar(k) is None:
            sink.error(at(k), f"{key}: expected a name, got {_kind(k)}")
        elif isinstance(v, yaml.ScalarNode):
            pairs.append((k, v))
        else:
            sink.error(at(v), f"{key}: {k.value}: expected a single value")
    return pairs


def _scalar(node: yaml.Node) -> str | None:
    """The text of a scalar node; None for a list or a mapping."""
    return node.value if isinstance(node, yaml.ScalarNode) else None


def _kind(node: yaml.Node) -> str:
    return "a list" if isinstance(node, yaml.SequenceNode) else "a mapping"


class CommandLineValue(str):
    """An attribute value as typed after ``--set F.attr=``: text, read by the attribute's
    type (:func:`typed_text`)."""


_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def typed_text(text: str, kind: str) -> AttributeValue:
    """``text`` read as a value of attribute type ``kind`` (``string`` takes it as it is),
    or None when it is not one: ``true``/``false``, a decimal int, a decimal number."""
    if kind == "string":
        return str(text)
    if kind == "bool":
        return {"true": True, "false": False}.get(text)
    if kind == "int":
        return literals.int_literal(text, literals.INT64_MAX)
    if kind == "double" and _NUMBER.fullmatch(text):
        return float(text)
    return None


def _value(text: str) -> tuple[object, str | None]:
    """(value, None) for a YAML scalar, or (None, why not): an unknown tag or a tagged
    value that does not convert (``!!float x``) is the user's error, not ours."""
    try:
        return yaml.safe_load(text), None
    except yaml.MarkedYAMLError as exc:
        return None, f"invalid YAML value: {exc.problem or exc.context}"
    except (yaml.YAMLError, ValueError, TypeError) as exc:
        return None, f"invalid YAML value: {exc}"


def _deployment(node, at, sink, selection: ProductSelection) -> None:
    if not isinstance(node, yaml.MappingNode):
        sink.error(at(node), "deployment: expected CONTAINER: {robot_id: ..., url: ...}")
        return
    for container_node, settings in node.value:
        container = _scalar(container_node)
        if container is None or not IDENT.fullmatch(container):
            shown = repr(container) if container is not None else _kind(container_node)
            sink.error(at(container_node), f"deployment: {shown} is not a container name")
            continue
        selection.locations[f"deployment:{container}"] = at(container_node)
        values = {}
        for k, v in _pairs(settings, at, sink, f"deployment: {container}"):
            pattern = DEPLOYMENT_KEYS.get(k.value)
            if pattern is None:
                sink.error(at(k), f"deployment: unknown setting {k.value!r} (robot_id, url)")
            elif not pattern.fullmatch(v.value):
                sink.error(at(v), f"deployment: {k.value} {v.value!r} is not valid")
            else:
                values[k.value] = v.value
        selection.deployment[container] = values


def apply_overrides(
    selection: ProductSelection, sharing: list[str], settings: list[str]
) -> ProductSelection:
    """Command-line ``--sharing F=mode`` and ``--set F.attr=value`` win over the file."""
    sink = DiagnosticSink()
    for text in sharing:
        where = Location("--sharing", 1, 1)
        feature, _, mode = text.partition("=")
        if not IDENT.fullmatch(feature) or mode not in SHARING_MODES:
            sink.error(where, f"{text!r}: expected FEATURE=private|protected|public")
            continue
        selection.sharing[feature] = mode
        selection.locations[f"sharing:{feature}"] = where
    for text in settings:
        where = Location("--set", 1, 1)
        key, _, value = text.partition("=")
        if not re.fullmatch(r"[A-Za-z_]\w*\.[A-Za-z_]\w*", key, re.ASCII) or not value:
            sink.error(where, f"{text!r}: expected FEATURE.ATTRIBUTE=VALUE")
            continue
        # read by the attribute's declared type when the product is resolved, not as YAML
        # (which would make `off` a bool, `2024-01-01` a date and `#3` nothing)
        selection.attributes[key] = CommandLineValue(value)
        selection.locations[key] = where
    sink.raise_if_errors()
    return selection
