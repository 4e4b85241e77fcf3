"""The Resolution Model language (.rm): parse, resolve names into the .tsm and .fm, check.

A resolution model names its template system model and feature model by paths
relative to itself; every feature, node, interface, topic, parameter and container it
mentions is resolved here, so the engine only ever sees references that exist and
whose types agree. Problems are reported all at once, located in the .rm file. The
text is read by ``rm_reader`` (fast) or, for what it leaves, by textX: both give the
same tree.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache
from itertools import zip_longest
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from spl.core.diagnostics import Diagnostic, DiagnosticSink, Location, ModelError, counted
from spl.core.emf import adopt, forget_references
from spl.dsl import literals, rosnames
from spl.dsl.fm.language import all_features
from spl.dsl.grammar_comments import is_comment
from spl.dsl.parse_tree import Positions
from spl.dsl.rm import reader as rm_reader, reuse as rm_reuse
from spl.dsl.rm.messages import (
    agree,
    name_taken,
    new_topic_clash,
    new_topic_ros_name_clash,
    not_served_here,
    same_container_bridge,
    same_topic,
)
from spl.dsl.rm.models import header_lines, referenced_models
from spl.dsl.rm.names import BRIDGE_FORMS, NameProblem, Names
from spl.dsl.textx_text import model_from_text
from spl.dsl.tsm.calling import call_problem
from spl.dsl.tsm.data import PERIOD_RANGE, period_fits
from spl.dsl.workspace import Workspace, text_of
from spl.metamodels import rm as rm_metamodel, tsm as tsm_metamodel
from spl.metamodels.interface_kinds import kind_of, with_article

if TYPE_CHECKING:
    from spl.metamodels import fm_types, rm_types, tsm_types

# The one product-line check (spl check DIR, resolver/line_checks.py) this parser makes:
# a migration must name another, existing container.
MIGRATION_TARGET = "SPL013"
CONNECT_SERVER = ("connect {client} to server {server}", "connected")  # binding a client
CONNECT_BRIDGE = ("connect bridge {client} -> {server}", "bridged")  # to its server (rm.tx)


@dataclass
class ResolutionModelFiles:
    """A resolution model together with the two models it refers to."""

    rm: rm_types.ResolutionModel
    tsm: tsm_types.System
    fm: fm_types.FeatureModel
    path: Path


@cache
def _grammar() -> Any:
    from textx import metamodel_from_file  # only what the fast reader leaves needs textX

    return metamodel_from_file(str(Path(__file__).with_name("rm.tx")), use_regexp_group=False)


def parse_file(path: str | Path, workspace: Workspace | None = None) -> rm_types.ResolutionModel:
    return load(path, workspace).rm


def summary(model: rm_types.ResolutionModel) -> str:
    transformations = sum(len(e.transformations) for e in model.elements)
    elements = counted(len(model.elements), "resolution element")
    return f"{elements}, {counted(transformations, 'transformation')}"


def load(path: str | Path, workspace: Workspace | None = None) -> ResolutionModelFiles:
    """Parse a .rm file and the .tsm and .fm it names, as ``workspace`` has them (ModelError)."""
    path = Path(path)
    return parse_text(text_of(path, workspace), str(path), base=path.parent, workspace=workspace)


def parse_text(
    text: str,
    filename: str = "<string>",
    base: Path | None = None,
    workspace: Workspace | None = None,
) -> ResolutionModelFiles:
    base = base or Path(filename).parent
    again = rm_reuse.still_built(workspace, text, filename, base)  # the editor's model
    if again is not None:
        return ResolutionModelFiles(*again, Path(filename))
    # the fast reader takes what it can; textX parses the rest and words syntax errors
    tree = rm_reader.read(text)
    if tree is None:
        tree = _textx_tree(text, filename)
    positions = Positions(text, filename)
    sink = DiagnosticSink()
    header = header_lines(text, positions, positions.of(tree))
    system, feature_model = referenced_models(tree, header, base, sink, workspace)
    sink.raise_if_errors()
    taken = rm_reuse.taken_over(workspace, text, filename, tree, system, feature_model)
    model = _Builder(positions, system, feature_model, sink).build(tree, taken)
    model.tsmPath, model.fmPath = tree.tsm, tree.fm
    rm_reuse.remember(workspace, text, filename, tree, header, system, feature_model, model, sink)
    sink.raise_if_errors()
    return ResolutionModelFiles(model, system, feature_model, Path(filename))


def _textx_tree(text: str, filename: str) -> Any:
    """textX's parse tree of ``text``; a syntax error as a located ModelError."""
    from textx import TextXSyntaxError

    try:
        return model_from_text(_grammar(), text, filename)
    except TextXSyntaxError as exc:
        rules = [r for r in exc.expected_rules or [] if not is_comment(r)]
        expected = ", ".join(sorted({_expected(r) for r in rules})) or None
        reason = exc.message.split(" at position")[0]
        if expected:
            reason = f"syntax error: expected {expected}"
        raise ModelError([Diagnostic(Location(filename, exc.line, exc.col), reason)]) from None


# What a syntax error says the grammar expected, for the rules that are patterns (their
# regular expressions are no words for a user) and the end of the file (its object's
# repr, with a memory address, made the message differ from run to run).
_RULE_WORDS = {
    "EOF": "end of file",
    "Ident": "a name (ASCII letters, digits and '_', not starting with a digit)",
    "Number": "a number",
    "RosType": "a type package/Type",
}


def _expected(rule: Any) -> str:
    """How a syntax error names what the grammar expected at the spot."""
    return _RULE_WORDS.get(getattr(rule, "rule_name", ""), str(rule))


class _Builder:
    """Turns the parse tree into an rm.ResolutionModel with references into the models.

    Statements are read in file order through :class:`~spl.dsl.rm.names.Names`, which
    follows the model as the statements before leave it; what cannot be known before a
    product is chosen is checked again by the Resolution Engine (docs/semantics.md)."""

    def __init__(self, positions: Positions, system: Any, feature_model: Any, sink: DiagnosticSink):
        self.positions = positions
        self.sink = sink
        self.R = rm_metamodel()
        self.T = tsm_metamodel()
        self.names = Names(system)
        self.features = {f.name: f for f in all_features(feature_model)}

    # -- locations -------------------------------------------------------------------
    def loc(self, node: Any) -> Location:
        return self.positions.of(node)

    def locate(self, element: Any, node: Any) -> Any:
        where = self.loc(node)
        element.srcFile, element.srcLine, element.srcCol = where.file, where.line, where.col
        return element

    def error(self, node: Any, message: str, code: str | None = None) -> None:
        self.sink.error(self.loc(node), message, code)

    # -- building -------------------------------------------------------------------
    def build(self, tree: Any, taken: Sequence[Any] = ()) -> Any:
        """The model of ``tree``; ``taken``, when given: per element, the last model's to
        take over (:func:`spl.dsl.rm.reuse.taken_over`), or None to build it."""
        model = self.locate(self.R.ResolutionModel(name=tree.name), tree)
        elements = []
        for element_tree, kept in zip_longest(tree.elements, taken):
            element = self._element(element_tree) if kept is None else self.names.taken(kept)
            if element is not None:
                elements.append(element)
        if elements:
            adopt(model, "elements", elements)
        return model

    def _element(self, tree: Any) -> Any:
        feature = self.features.get(tree.feature)
        if feature is None:
            self.error(tree, f"unknown feature {tree.feature}")
        element = self.locate(self.R.ResolutionElement(activeIfSelected=not tree.negated), tree)
        element.feature = feature
        self.names.begin_element(element)
        for stmt in tree.statements:
            kind = type(stmt).__name__
            if kind == "Require":
                for ref in stmt.refs:
                    try:
                        element.required.append(self.names.element(ref, "node or store"))
                    except NameProblem as problem:
                        self.error(stmt, str(problem))
                continue
            try:
                transformation = getattr(self, f"_{kind}")(stmt)
            except NameProblem as problem:
                self.error(stmt, str(problem))
                continue
            if transformation is not None:
                element.transformations.append(self.locate(transformation, stmt))
                self.names.apply(transformation)
        if feature is None:  # refused: the elements it names keep no record of it
            forget_references(element)
        return element if feature is not None else None

    def _typed(self, stmt, interface, fits: bool, role: str) -> bool:
        """``fits``, else an error: the interface is not a ``role``."""
        if not fits:
            named = f"{interface.eContainer().name}.{interface.name}"
            self.error(stmt, f"{named} is {kind_of(interface).a_class}, not {with_article(role)}")
        return fits

    def _topic_reference(self, container: Any, name: str, stmt: Any) -> Any:
        reference = self.R.TopicReference(container=container, name=name)
        return self.locate(reference, stmt)

    # -- transformations ------------------------------------------------------------
    def _ImplementationStmt(self, stmt):
        node = self.names.element(stmt.node)
        package, executable = stmt.implementation.split("/", 1)
        problem = rosnames.problem_implementation(stmt.implementation)
        if problem:
            self.error(stmt, problem)
            return None
        args = None if stmt.args is None else stmt.args.value  # as the .tsm's (docs/rm.md)
        if args is not None and (problem := rosnames.problem_args(args)):
            self.error(stmt.args, problem)
            return None
        given = {} if args is None else {"args": args}  # unset: the node keeps its own
        return self.R.Implementation(node=node, package=package, executable=executable, **given)

    def _ConnectTopicStmt(self, stmt):
        interface = self.names.interface(stmt.interface)
        if not self._typed(stmt, interface, kind_of(interface).on_topic, "publisher or subscriber"):
            return None
        container, topics = self.names.topic_reference(stmt.topic, _node(interface))
        if not any(agree(interface, topic) for topic in topics):
            self._same_type(stmt, interface, topics[0])
            return None
        topic = self._topic_reference(container, stmt.topic.split(".")[-1], stmt)
        return self.R.ConnectToTopic(interface=interface, topic=topic)

    def _ConnectNewTopicStmt(self, stmt):
        interface = self.names.interface(stmt.interface)
        if not self._typed(stmt, interface, kind_of(interface).on_topic, "publisher or subscriber"):
            return None
        ros_name = stmt.rosName or f"/{stmt.name}"
        problem = rosnames.problem_graph_name(ros_name)
        if problem:
            self.error(stmt, f"new topic {stmt.name}: {problem}")
            return None
        topic = self.locate(self.T.Topic(name=stmt.name, type=stmt.type, rosName=ros_name), stmt)
        if not self._same_type(stmt, interface, topic):
            return None
        places = self.names.places(_node(interface))
        clashes = [c for c in (self._new_topic_clash(stmt.name, p, topic) for p in places) if c]
        if len(clashes) == len(places):  # refused wherever the node can be
            self.error(stmt, clashes[0])
            return None
        return self.R.ConnectToNewTopic(interface=interface, topic=topic)

    def _new_topic_clash(self, name: str, container: Any, topic: Any) -> str | None:
        """Why ``new topic`` cannot create ``topic`` in ``container``, or None: the name is
        another topic's, or its ROS name is a topic's of another type."""
        existing = self.names.topic(container, name)
        if existing is not None and not self._same_new_topic(existing, topic):
            return new_topic_clash(name, container, existing, self.names.is_created(existing))
        other = self.names.ros_name_taken(container, topic)
        if other is not None:
            return new_topic_ros_name_clash(name, container, other, topic)
        return None

    def _same_new_topic(self, existing: Any, topic: Any) -> bool:
        """Two `new topic` statements creating one topic (same type and ROS name) agree."""
        return self.names.is_created(existing) and same_topic(existing, topic)

    def _service_pair(
        self, stmt: Any, client: Any, server: Any, written: tuple[str, str]
    ) -> tuple[tsm_types.ServiceClient, tsm_types.ServiceServer] | None:
        """The client and server of a statement ``written`` so, if they agree, else None."""
        problem = call_problem(client, server, *written)
        if problem is not None:
            self.error(stmt, problem.message)
            return None
        return cast("tsm_types.ServiceClient", client), cast("tsm_types.ServiceServer", server)

    def _ConnectServerStmt(self, stmt):
        client = self.names.interface(stmt.client)
        server = self.names.interface(stmt.server)
        pair = self._service_pair(stmt, client, server, CONNECT_SERVER)
        if pair is None:
            return None
        client, server = pair
        client_places = self.names.places(_node(client))
        server_places = self.names.places(_node(server))
        if not {id(c) for c in client_places} & {id(c) for c in server_places}:
            self.error(stmt, not_served_here(client, server, server_places, client_places))
            return None
        return self.R.ConnectService(client=client, server=server)

    def _ConnectBridgeStmt(self, stmt):
        source = self.names.bridge_end(stmt.source)
        target = self.names.bridge_end(stmt.target)
        if source.topic is not None and target.topic is not None:
            if source.container is target.container:
                self.error(stmt, "a bridge connects two different containers")
                return None
            if not self._same_type(stmt, source.topic, target.topic):
                return None
            return self.R.ConnectBridge(
                sourceTopic=self._topic_reference(source.container, source.topic.name, stmt),
                targetTopic=self._topic_reference(target.container, target.topic.name, stmt),
            )
        if source.interface is not None and target.interface is not None:
            pair = self._service_pair(stmt, source.interface, target.interface, CONNECT_BRIDGE)
            if pair is None:
                return None
            client, server = pair
            client_places = self.names.places(_node(client))
            server_places = self.names.places(_node(server))
            if len(client_places) == len(server_places) == 1 and client_places == server_places:
                self.error(stmt, same_container_bridge(client, server, client_places[0]))
                return None
            return self.R.ConnectBridge(client=client, server=server)
        self.error(stmt, BRIDGE_FORMS)
        return None

    def _ParameterStmt(self, stmt):
        parameter, refinement = self.names.parameter(stmt.parameter)
        if refinement is not None:
            ptype, what = "double", f"{stmt.parameter}"
        else:
            parameter = cast("tsm_types.Parameter", parameter)  # one of the two is set
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
            if not literals.attribute_fits(attribute.type.name, ptype):
                named = f"{feature.name}.{attribute.name}"
                self.error(stmt, f"attribute {named} is {attribute.type.name}, {what} is {ptype}")
                return None
            return self.R.ParameterValue(
                parameter=parameter, refinement=refinement, attribute=attribute
            )
        text, problem = literals.parameter_literal(value, ptype)
        if problem or text is None:  # (no problem: a text)
            self.error(stmt, f"{what} is {ptype}: {problem}")
            return None
        if refinement is not None and not period_fits(float(text)):
            self.error(stmt, f"{what} must be {PERIOD_RANGE}")
            return None
        return self.R.ParameterValue(parameter=parameter, refinement=refinement, value=text)

    def _MigrateStmt(self, stmt):
        target = self.names.containers.get(stmt.container)
        if target is None:
            self.error(stmt, f"unknown container {stmt.container}", MIGRATION_TARGET)
        node = self.names.element(stmt.node)
        if target is None:
            return None
        if node.eContainer() is target:
            self.error(  # not "already in": an earlier migration may have moved it
                stmt,
                f"node {node.name} is declared in container {target.name}: a migration moves "
                "a node to another container",
                MIGRATION_TARGET,
            )
            return None
        resident = self.names.declared_node(target, node.name)
        if resident is not None and self.names.places(resident) == [target]:
            self.error(stmt, name_taken(node, target, resident))
            return None
        return self.R.NodeMigration(node=node, target=target)

    def _same_type(self, stmt, a, b) -> bool:
        if not (same := agree(a, b)):
            self.error(stmt, f"type mismatch: {a.name} is {a.type}, {b.name} is {b.type}")
        return same


def _node(interface: tsm_types.Interface) -> tsm_types.Node:
    """The node of an interface the .rm names (a node's, never an endpoint's)."""
    return cast("tsm_types.Node", interface.eContainer())
