"""The Resolution Model language (.rm): parse, resolve names into the .tsm and .fm, check.

A resolution model names its template system model and feature model by paths
relative to itself; every feature, node, interface, topic, parameter and container it
mentions is resolved here, so the engine only ever sees references that exist and
whose types agree. Problems are reported all at once, located in the .rm file.
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass
from functools import cache
from importlib.resources import files
from pathlib import Path
from typing import Any

from textx import TextXSyntaxError, get_location, metamodel_from_file

from spl.diagnostics import Diagnostic, DiagnosticSink, Location, ModelError, counted, read_source
from spl.dsl import literals, rosnames
from spl.metamodels import rm as rm_metamodel
from spl.metamodels import tsm as tsm_metamodel

# The one product-line check (spl check DIR, resolver/line_checks.py) this parser makes:
# a migration must name another, existing container.
MIGRATION_TARGET = "SPL013"


@dataclass
class ResolutionModelFiles:
    """A resolution model together with the two models it refers to."""

    rm: Any  # rm.ResolutionModel
    tsm: Any  # tsm.System
    fm: Any  # fm.FeatureModel
    path: Path


@cache
def _grammar():
    return metamodel_from_file(str(files(__package__).joinpath("rm.tx")), use_regexp_group=False)


def parse_file(path: str | Path) -> Any:
    return load(path).rm


def summary(model: Any) -> str:
    transformations = sum(len(e.transformations) for e in model.elements)
    elements = counted(len(model.elements), "resolution element")
    return f"{elements}, {counted(transformations, 'transformation')}"


def load(path: str | Path) -> ResolutionModelFiles:
    """Parse a .rm file and the .tsm and .fm it names; raise ModelError on any problem."""
    path = Path(path)
    return parse_text(read_source(path), str(path), base=path.parent)


def parse_text(
    text: str, filename: str = "<string>", base: Path | None = None
) -> ResolutionModelFiles:
    try:
        tree = _grammar().model_from_str(text, file_name=filename)
    except TextXSyntaxError as exc:
        expected = ", ".join(sorted({str(r) for r in (exc.expected_rules or [])})) or None
        reason = exc.message.split(" at position")[0]
        if expected:
            reason = f"syntax error: expected {expected}"
        raise ModelError([Diagnostic(Location(filename, exc.line, exc.col), reason)]) from None
    base = base or Path(filename).parent
    sink = DiagnosticSink()
    tsm_path = _model_path(base, tree.tsm)
    fm_path = _model_path(base, tree.fm)
    system = _load_referenced(
        "spl.dsl.tsm", "parse_file", tsm_path, tree, "tsm", filename, sink, {".tsm"}
    )
    feature_model = _load_feature_model(fm_path, tree, filename, sink)
    sink.raise_if_errors()
    model = _Builder(filename, system, feature_model, sink).build(tree)
    sink.raise_if_errors()
    model.tsmPath, model.fmPath = tree.tsm, tree.fm
    return ResolutionModelFiles(model, system, feature_model, Path(filename))


def _model_path(base: Path, relative: str) -> Path:
    return (base / relative) if not Path(relative).is_absolute() else Path(relative)


def _tree_location(filename: str, node: Any) -> Location:
    loc = get_location(node)
    return Location(filename, loc["line"], loc["col"])


def _load_referenced(module, function, path, tree, attr, filename, sink, suffixes):
    where = _tree_location(filename, tree)
    if path.suffix not in suffixes:
        sink.error(where, f"{attr} {str(path)!r}: expected a {' or '.join(sorted(suffixes))} file")
        return None
    if not path.is_file():
        sink.error(where, f"{attr} file {str(path)!r} not found")
        return None
    try:
        return getattr(importlib.import_module(module), function)(path)
    except ModelError as exc:
        sink.diagnostics.extend(exc.diagnostics)
        return None


def _load_feature_model(path: Path, tree: Any, filename: str, sink: DiagnosticSink) -> Any:
    """The feature model may be written in .fm, UVL or FeatureIDE XML."""
    return _load_referenced(
        "spl.dsl.fm_formats",
        "load_feature_model",
        path,
        tree,
        "fm",
        filename,
        sink,
        {".fm", ".uvl", ".xml"},
    )


class _Builder:
    """Turns the textX tree into an rm.ResolutionModel with references into the models."""

    def __init__(self, filename: str, system: Any, feature_model: Any, sink: DiagnosticSink):
        self.filename = filename
        self.sink = sink
        self.R = rm_metamodel()
        self.T = tsm_metamodel()
        self.containers = {c.name: c for c in system.containers}
        self.features = {f.name: f for f in _all_features(feature_model.root)}
        self.nodes: dict[str, list[Any]] = {}
        self.stores: dict[str, list[Any]] = {}
        for container in system.containers:
            for node in container.nodes:
                self.nodes.setdefault(node.name, []).append(node)
            for store in container.stores:
                self.stores.setdefault(store.name, []).append(store)
        # topics created by `connect ... to new topic`, per container, visible to every element
        self.new_topics: dict[tuple[str, str], Any] = {}

    # -- locations -------------------------------------------------------------------
    def loc(self, node: Any) -> Location:
        return _tree_location(self.filename, node)

    def locate(self, element: Any, node: Any) -> Any:
        where = self.loc(node)
        element.srcFile, element.srcLine, element.srcCol = where.file, where.line, where.col
        return element

    def error(self, node: Any, message: str, code: str | None = None) -> None:
        self.sink.error(self.loc(node), message, code)

    # -- building -------------------------------------------------------------------
    def build(self, tree: Any) -> Any:
        model = self.locate(self.R.ResolutionModel(name=tree.name), tree)
        self._declare_new_topics(tree)
        for element_tree in tree.elements:
            element = self._element(element_tree)
            if element is not None:
                model.elements.append(element)
        return model

    def _declare_new_topics(self, tree: Any) -> None:
        for element_tree in tree.elements:
            for stmt in element_tree.statements:
                if type(stmt).__name__ != "ConnectNewTopicStmt":
                    continue
                interface = self._interface(stmt, stmt.interface)
                if interface is None:
                    continue
                container = interface.eContainer().eContainer()
                ros_name = stmt.rosName or f"/{stmt.name}"
                problem = rosnames.problem_graph_name(ros_name)
                if problem:
                    self.error(stmt, f"new topic {stmt.name}: {problem}")
                key = (container.name, stmt.name)
                if any(t.name == stmt.name for t in container.topics):
                    self.error(
                        stmt,
                        f"new topic {stmt.name}: container {container.name} already has a topic "
                        f"named {stmt.name} (connect to it with 'to topic {stmt.name}')",
                    )
                    continue
                earlier = self.new_topics.get(key)
                if earlier is not None:
                    if (earlier.type, earlier.rosName) != (stmt.type, ros_name):
                        self.error(
                            stmt,
                            f"new topic {stmt.name} in {container.name} is declared again "
                            f"with another type or ROS name (first at line {earlier.srcLine})",
                        )
                    continue
                topic = self.T.Topic(name=stmt.name, type=stmt.type, rosName=ros_name)
                self.new_topics[key] = self.locate(topic, stmt)

    def _element(self, tree: Any) -> Any:
        feature = self.features.get(tree.feature)
        if feature is None:
            self.error(tree, f"unknown feature {tree.feature}")
        element = self.locate(self.R.ResolutionElement(activeIfSelected=not tree.negated), tree)
        element.feature = feature
        for stmt in tree.statements:
            kind = type(stmt).__name__
            if kind == "Require":
                for ref in stmt.refs:
                    target = self._required(stmt, ref)
                    if target is not None:
                        element.required.append(target)
                continue
            transformation = getattr(self, f"_{kind}")(stmt)
            if transformation is not None:
                element.transformations.append(self.locate(transformation, stmt))
        return element if feature is not None else None

    # -- name resolution ------------------------------------------------------------
    def _by_qualified(self, stmt, ref: str, index: dict[str, list[Any]], what: str):
        parts = ref.split(".")
        if len(parts) == 2:
            container = self.containers.get(parts[0])
            if container is None:
                self.error(stmt, f"unknown container {parts[0]}")
                return None
            found = [x for x in index.get(parts[1], []) if x.eContainer() is container]
            name = parts[1]
        elif len(parts) == 1:
            found = index.get(parts[0], [])
            name = parts[0]
        else:
            self.error(stmt, f"{ref}: expected {what} or CONTAINER.{what}")
            return None
        if not found:
            self.error(stmt, f"unknown {what} {ref}")
            return None
        if len(found) > 1:
            options = ", ".join(f"{x.eContainer().name}.{name}" for x in found)
            self.error(stmt, f"{what} {ref} is ambiguous: write one of {options}")
            return None
        return found[0]

    def _node(self, stmt, ref: str):
        return self._by_qualified(stmt, ref, self.nodes, "node")

    def _required(self, stmt, ref: str):
        parts = ref.split(".")
        name = parts[-1]
        index = self.stores if name in self.stores and name not in self.nodes else self.nodes
        return self._by_qualified(stmt, ref, index, "store" if index is self.stores else "node")

    def _member(self, stmt, ref: str, attr: str, what: str):
        parts = ref.split(".")
        if len(parts) < 2:
            self.error(stmt, f"{ref}: expected NODE.{what}")
            return None
        node = self._node(stmt, ".".join(parts[:-1]))
        if node is None:
            return None
        member = next((x for x in getattr(node, attr) if x.name == parts[-1]), None)
        if member is None:
            self.error(stmt, f"node {node.name} has no {what} {parts[-1]}")
        return member

    def _interface(self, stmt, ref: str):
        return self._member(stmt, ref, "interfaces", "interface")

    def _topic_in(self, stmt, container, name: str):
        topic = next((t for t in container.topics if t.name == name), None)
        if topic is None:
            topic = self.new_topics.get((container.name, name))
        if topic is None:
            self.error(stmt, f"unknown topic {name} in container {container.name}")
        return topic

    def _typed(self, stmt, interface, kinds: tuple[str, ...], role: str) -> bool:
        if interface.eClass.name not in kinds:
            owner = interface.eContainer().name
            self.error(
                stmt,
                f"{owner}.{interface.name} is a {interface.eClass.name}, not a {role}",
            )
            return False
        return True

    # -- transformations ------------------------------------------------------------
    def _ImplementationStmt(self, stmt):
        node = self._node(stmt, stmt.node)
        if node is None:
            return None
        package, executable = stmt.implementation.split("/", 1)
        problem = rosnames.problem_implementation(stmt.implementation)
        if problem:
            self.error(stmt, problem)
            return None
        return self.R.Implementation(node=node, package=package, executable=executable)

    def _ConnectTopicStmt(self, stmt):
        interface = self._interface(stmt, stmt.interface)
        if interface is None or not self._typed(
            stmt, interface, ("Publisher", "Subscriber"), "publisher or subscriber"
        ):
            return None
        topic = self._topic_in(stmt, interface.eContainer().eContainer(), stmt.topic)
        if topic is None or not self._same_type(stmt, interface, topic):
            return None
        return self.R.ConnectToTopic(interface=interface, topic=topic)

    def _ConnectNewTopicStmt(self, stmt):
        interface = self._interface(stmt, stmt.interface)
        if interface is None or not self._typed(
            stmt, interface, ("Publisher", "Subscriber"), "publisher or subscriber"
        ):
            return None
        container = interface.eContainer().eContainer()
        declared = self.new_topics.get((container.name, stmt.name))
        if declared is None or not self._same_type(stmt, interface, declared):
            return None
        topic = self.T.Topic(name=declared.name, type=declared.type, rosName=declared.rosName)
        return self.R.ConnectToNewTopic(interface=interface, topic=self.locate(topic, stmt))

    def _service_pair(self, stmt, client_name: str, server_name: str):
        """The client and server interfaces a statement names, or None (error reported)."""
        client = self._interface(stmt, client_name)
        server = self._interface(stmt, server_name)
        if client is None or server is None:
            return None
        if not (
            self._typed(stmt, client, ("ServiceClient",), "service client")
            and self._typed(stmt, server, ("ServiceServer",), "service server")
        ):
            return None
        return client, server

    def _ConnectServerStmt(self, stmt):
        pair = self._service_pair(stmt, stmt.client, stmt.server)
        if pair is None:
            return None
        client, server = pair
        client_container = client.eContainer().eContainer()
        server_container = server.eContainer().eContainer()
        if client_container is not server_container:
            self.error(
                stmt,
                f"{stmt.server} is served in container {server_container.name}, not in "
                f"{client_container.name}: use 'connect bridge {client_container.name}."
                f"{stmt.client} -> {server_container.name}.{stmt.server}'",
            )
            return None
        if not self._same_type(stmt, client, server):
            return None
        return self.R.ConnectService(client=client, server=server)

    def _ConnectBridgeStmt(self, stmt):
        source, target = stmt.source.split("."), stmt.target.split(".")
        if len(source) == len(target) == 2:
            containers = [self.containers.get(source[0]), self.containers.get(target[0])]
            for name, container in zip((source[0], target[0]), containers, strict=True):
                if container is None:
                    self.error(stmt, f"unknown container {name}")
            if None in containers:
                return None
            if containers[0] is containers[1]:
                self.error(stmt, "a bridge connects two different containers")
                return None
            topics = [
                self._topic_in(stmt, containers[0], source[1]),
                self._topic_in(stmt, containers[1], target[1]),
            ]
            if None in topics or not self._same_type(stmt, *topics):
                return None
            return self.R.ConnectBridge(sourceTopic=topics[0], targetTopic=topics[1])
        if len(source) == len(target) == 3:
            pair = self._service_pair(stmt, stmt.source, stmt.target)
            if pair is None:
                return None
            client, server = pair
            if client.eContainer().eContainer() is server.eContainer().eContainer():
                self.error(stmt, "a bridge connects two different containers")
                return None
            if not self._same_type(stmt, client, server):
                return None
            return self.R.ConnectBridge(client=client, server=server)
        self.error(
            stmt,
            "a bridge is CONTAINER.TOPIC -> CONTAINER.TOPIC or "
            "CONTAINER.NODE.CLIENT -> CONTAINER.NODE.SERVER",
        )
        return None

    def _ParameterStmt(self, stmt):
        refinement = self._refinement(stmt, stmt.parameter)
        if refinement is not None:
            parameter, ptype, what = None, "double", f"{stmt.parameter}"
        else:
            parameter = self._member(stmt, stmt.parameter, "parameters", "parameter")
            if parameter is None:
                return None
            ptype, what = parameter.type.name, f"parameter {parameter.name}"
        value = stmt.value
        if type(value).__name__ == "FeatureAttributeValue":
            feature = self.features.get(value.feature)
            if feature is None:
                self.error(stmt, f"unknown feature {value.feature}")
                return None
            attribute = next((a for a in feature.attributes if a.name == value.attribute), None)
            if attribute is None:
                self.error(stmt, f"feature {feature.name} has no attribute {value.attribute}")
                return None
            if not _attribute_fits(attribute.type.name, ptype):
                self.error(
                    stmt,
                    f"attribute {feature.name}.{attribute.name} is {attribute.type.name}, "
                    f"{what} is {ptype}",
                )
                return None
            return self.R.ParameterValue(
                parameter=parameter, refinement=refinement, attribute=attribute
            )
        text, problem = canonical_parameter_value(value, ptype)
        if problem:
            self.error(stmt, f"{what} is {ptype}: {problem}")
            return None
        if refinement is not None and float(text) <= 0:
            self.error(stmt, f"{what} must be a positive number of seconds")
            return None
        return self.R.ParameterValue(parameter=parameter, refinement=refinement, value=text)

    def _refinement(self, stmt, ref: str):
        """``[CONTAINER.]STORE.REFINED_TYPE.period``: the period of a store's transformer."""
        parts = ref.split(".")
        if len(parts) < 3 or parts[-1] != "period" or parts[-3] not in self.stores:
            return None
        store = self._by_qualified(stmt, ".".join(parts[:-2]), self.stores, "store")
        if store is None:
            return None
        refinement = next((r for r in store.refinements if r.output.name == parts[-2]), None)
        if refinement is None:
            self.error(stmt, f"store {store.name} has no refinement into {parts[-2]}")
        return refinement

    def _MigrateStmt(self, stmt):
        node = self._node(stmt, stmt.node)
        target = self.containers.get(stmt.container)
        if target is None:
            self.error(stmt, f"unknown container {stmt.container}", MIGRATION_TARGET)
        if node is None or target is None:
            return None
        if node.eContainer() is target:
            self.error(
                stmt, f"node {node.name} is already in container {target.name}", MIGRATION_TARGET
            )
            return None
        return self.R.NodeMigration(node=node, target=target)

    def _same_type(self, stmt, a, b) -> bool:
        if a.type and b.type and a.type != b.type:
            self.error(stmt, f"type mismatch: {a.name} is {a.type}, {b.name} is {b.type}")
            return False
        return True


def _all_features(feature: Any):
    yield feature
    for group in feature.groups:
        for child in group.features:
            yield from _all_features(child)


def _attribute_fits(attribute_type: str, parameter_type: str) -> bool:
    return attribute_type == parameter_type or (attribute_type, parameter_type) in {
        ("int", "double"),
        ("string", "yaml"),
    }


def canonical_parameter_value(value: Any, ptype: str) -> tuple[str | None, str | None]:
    """The canonical text of a literal for a parameter of type ``ptype`` (TSM convention)."""
    kind, text = type(value).__name__, value.value
    if kind == "StringValue":
        if ptype not in ("string", "yaml"):
            return None, f"expected a {ptype} value, got a string"
        if any(ord(c) < 32 and c not in "\n\t" for c in text):
            return None, "control characters are not allowed in values"
        if ptype == "yaml":
            problem = literals.problem_yaml(text)
            if problem:
                return None, problem
        return text, None
    if kind == "BoolValue":
        return (text, None) if ptype == "bool" else (None, f"expected a {ptype} value, got {text}")
    if ptype == "int" and text.lstrip("+-").isdigit():
        value = literals.int_literal(text)
        return (str(value), None) if value is not None else (None, f"{text} is out of range")
    if ptype == "double":
        value = float(text)
        return (repr(value), None) if math.isfinite(value) else (None, f"{text} is out of range")
    return None, f"expected a {ptype} value, got {text}"
