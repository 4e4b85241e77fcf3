"""The extended Feature Model language (.fm): parse, build the pyecore model, check.

The grammar (``fm.tx``) only recognises the shape of the text; this module
turns the parse tree into an ``fm.FeatureModel`` (src/spl/metamodels/fm.ecore), resolves the
feature names used in constraints and reports every problem at once, located at the
offending name, so a user fixes a file in one pass. UVL and FeatureIDE XML readers
build the same model (``src/spl/dsl/interop/uvl.py``, ``src/spl/dsl/interop/featureide.py``);
``fm_printer`` writes it
back in the canonical form described there. The text is read by ``fm_reader`` (fast)
or, for what it leaves, by textX: both give the same tree.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from functools import cache
from pathlib import Path
from typing import Any, cast

from spl.core.diagnostics import (
    DiagnosticSink,
    Location,
    ModelError,
    counted,
)
from spl.dsl import literals
from spl.dsl.fm import reader as fm_reader
from spl.dsl.fm.capability import capability_condition
from spl.dsl.fm.syntax import syntax_diagnostic
from spl.dsl.fm.vocabulary import (
    ATTRIBUTE_TYPES as ATTRIBUTE_TYPES,
    IDENTIFIER as IDENTIFIER,
    OPERATORS as OPERATORS,
    RESERVED_WORDS as RESERVED_WORDS,
    SHARING_MODES as SHARING_MODES,
    balanced,
    canonical_value,
    formula_too_deep,
    is_feature_name as is_feature_name,
    too_deep,
)
from spl.dsl.parse_tree import Positions
from spl.dsl.textx_text import model_from_text
from spl.dsl.workspace import Workspace, last_built, text_of
from spl.metamodels import fm as fm_metamodel


@cache
def _grammar() -> Any:
    from textx import metamodel_from_file  # only what the fast reader leaves needs textX

    return metamodel_from_file(
        str(Path(__file__).with_name("fm.tx")), autokwd=True, use_regexp_group=False
    )


def parse_file(path: str | Path, workspace: Workspace | None = None) -> Any:
    """Parse a .fm file into an ``fm.FeatureModel``; raise ModelError with every problem.
    Read as the editor's ``workspace`` has it, when given (:mod:`spl.dsl.workspace`)."""
    path = Path(path)
    return parse_text(text_of(path, workspace), str(path), workspace)


def parse_text(text: str, filename: str = "<string>", workspace: Workspace | None = None) -> Any:
    """Parse .fm source text; ``filename`` is only used in locations. In an editor's
    ``workspace`` that keeps its line checks' models, a text built before gives the same
    model (a line's .rm built before refers to its features, and is then built no more)."""
    last = workspace.models if workspace is not None else None
    known = last_built(last.feature_models, text, filename) if last is not None else None
    if known is not None:
        return known
    model = _parse(text, filename)
    if last is not None:
        last.feature_models[filename] = (text, model)
    return model


def _parse(text: str, filename: str) -> Any:
    try:
        # the fast reader takes what it can; textX parses the rest and words syntax errors
        tree = fm_reader.read(text)
        if tree is None:
            tree = _textx_tree(text, filename)
        sink = DiagnosticSink()
        model = _Builder(text, filename, sink).build(tree)
    except RecursionError:
        raise ModelError([too_deep(filename)]) from None
    sink.raise_if_errors()
    return model


def _textx_tree(text: str, filename: str) -> Any:
    """textX's parse tree of ``text``; a syntax error as a located ModelError."""
    from textx import TextXSyntaxError

    try:
        return model_from_text(_grammar(), text, filename)
    except TextXSyntaxError as exc:
        raise ModelError([syntax_diagnostic(exc, filename)]) from None


def summary(model: Any) -> str:
    """One line for ``spl check``: how many features and constraints."""
    features = sum(1 for _ in all_features(model))
    constraints = len(model.constraints)
    return f"{counted(features, 'feature')}, {counted(constraints, 'constraint')}"


def all_features(model_or_feature: Any) -> Iterator[Any]:
    """Every feature of a model (or below a feature), parents before children."""
    start = getattr(model_or_feature, "root", model_or_feature)
    if start is None:
        return
    stack = [start]
    while stack:
        feature = stack.pop()
        yield feature
        children = [child for group in feature.groups for child in group.features]
        stack.extend(reversed(children))


def parent_of(feature: Any) -> Any:
    """The parent feature (None for the root)."""
    group = feature.eContainer()
    return group.eContainer() if group is not None and group.eClass.name == "Group" else None


def _unquote(literal: str) -> str:
    escapes = {"n": "\n", "t": "\t", '"': '"', "\\": "\\"}
    return re.sub(r"\\(.)", lambda m: escapes[m.group(1)], literal[1:-1])


class _Builder:
    """Turns the parse tree into an fm.FeatureModel, collecting located problems."""

    def __init__(self, text: str, filename: str, sink: DiagnosticSink) -> None:
        self.text = text
        self.filename = filename
        self.sink = sink
        self.F = fm_metamodel()
        self.positions = Positions(text, filename)
        self.features: dict[str, Any] = {}
        self.balance = False  # build and/or chains balanced (a constraint too deep left-deep)

    # -- locations -------------------------------------------------------------------
    def loc(self, node: Any) -> Location:
        return self.positions.of(node)

    def name_loc(self, decl: Any) -> Location:
        """Where the feature's name is written (after a leading ``abstract``)."""
        position = decl._tx_position
        if decl.abstract:
            match = re.compile(r"\b" + re.escape(decl.name) + r"\b").search(self.text, position)
            position = match.start() if match else position
        return self.positions.at(position)

    def locate(self, element: Any, where: Location) -> Any:
        element.srcFile, element.srcLine, element.srcCol = where.file, where.line, where.col
        return element

    # -- model -----------------------------------------------------------------------
    def build(self, tree: Any) -> Any:
        F = self.F
        model = self.locate(F.FeatureModel(name=tree.name), self.loc(tree))
        model.root = self.feature(tree.root)
        for constraint_tree in tree.constraints:
            reported = len(self.sink.diagnostics)
            formula = self.formula(constraint_tree.formula)
            refused = formula_too_deep(formula)
            if refused and len(self.sink.diagnostics) == reported:
                self.balance = True  # built left-deep; with its chains balanced it may fit
                formula = self.formula(constraint_tree.formula)
                self.balance = False
                refused = formula_too_deep(formula)
            if refused:
                self.sink.error(self.loc(constraint_tree), refused)
                continue
            constraint = self.locate(F.Constraint(), self.loc(constraint_tree))
            constraint.formula = formula
            model.constraints.append(constraint)
        return model

    def feature(self, decl: Any) -> Any:
        F = self.F
        where = self.name_loc(decl)
        feature = self.locate(F.Feature(name=decl.name, abstract=bool(decl.abstract)), where)
        earlier = self.features.get(decl.name)
        if earlier is not None:
            self.sink.error(
                where,
                f"duplicate feature {decl.name} (first declared at line {earlier.srcLine})",
            )
        else:
            self.features[decl.name] = feature
        if decl.head is not None:
            feature.groups.append(self.choice_group(decl.head))
        attribute_names: dict[str, Any] = {}
        # `mandatory A` `mandatory B` written one after the other share one group
        child_group = None
        for item in decl.items:
            kind = type(item).__name__
            if kind == "AttributeDecl":
                attribute = self.attribute(item)
                if item.name in _RESERVED_ATTRIBUTES:
                    self.sink.error(self.loc(item), _RESERVED_ATTRIBUTES[item.name])
                elif item.name == "original_name" and item.type != "string":
                    self.sink.error(
                        self.loc(item), "attribute original_name holds a name: it is a string"
                    )
                if item.name in attribute_names:
                    self.sink.error(
                        self.loc(item),
                        f"feature {decl.name} has two attributes named {item.name}",
                    )
                attribute_names[item.name] = attribute
                feature.attributes.append(attribute)
            elif kind == "SharingDecl":
                if feature.sharing is not None:
                    self.sink.error(
                        self.loc(item),
                        f"feature {decl.name} has two sharing attributes "
                        f"(first at line {feature.sharing.srcLine})",
                    )
                    continue
                config = self.locate(F.SharingConfig(), self.loc(item))
                config.mode = F.SharingMode.getEEnumLiteral(item.mode)
                feature.sharing = config
            elif kind == "CapabilityDecl":
                for node in item.conditions:
                    feature.capabilities.append(
                        capability_condition(node, self.loc(node), self.sink)
                    )
            elif kind == "Child":
                child = self.feature(item.feature)
                if child_group is None or child_group.kind.name != item.kind:
                    child_group = self.group(item.kind, item)
                    feature.groups.append(child_group)
                child_group.features.append(child)
            elif kind == "KindBlock":
                group = self.group(item.kind, item)
                group.features.extend(self.feature(member) for member in item.members)
                feature.groups.append(group)
                child_group = None
            else:
                feature.groups.append(self.choice_group(item))
                child_group = None
        return feature

    def group(self, kind: str, node: Any) -> Any:
        group = self.locate(self.F.Group(), self.loc(node))
        group.kind = self.F.GroupKind.getEEnumLiteral(kind)
        return group

    def choice_group(self, node: Any) -> Any:
        kind = type(node).__name__
        if kind == "XorGroup":
            group = self.group("alternative", node)
        elif kind == "OrGroup":
            group = self.group("or", node)
        else:
            group = self.group("cardinality", node)
            bound = literals.INT32_MAX
            lower = literals.int_literal(node.lower, bound)
            if node.upper in ("", None):
                upper = lower
            else:
                upper = -1 if node.upper == "*" else literals.int_literal(node.upper, bound)
            if lower is None or upper is None:
                problem = f": a bound is out of range (at most {bound})"
            elif upper == 0:
                problem = ": the upper bound must be at least 1"
            elif upper != -1 and lower > upper:
                problem = f" [{lower}..{upper}]: the lower bound exceeds the upper bound"
            elif lower > len(node.members):  # no product could choose that many
                count = len(node.members)
                written = f"[{lower}..{node.upper}]" if node.upper else f"[{lower}]"
                problem = (
                    f" {written}: the group has {count} feature{'s' * (count != 1)}, fewer "
                    "than its lower bound (no product could choose that many)"
                )
            else:
                problem = None
                group.lower, group.upper = lower, upper
            if problem:
                self.sink.error(self.loc(node), f"bad cardinality{problem}")
        group.features.extend(self.feature(member) for member in node.members)
        return group

    def attribute(self, item: Any) -> Any:
        F = self.F
        attribute = self.locate(F.Attribute(name=item.name), self.loc(item))
        attribute.type = F.AttributeType.getEEnumLiteral(item.type)
        literal = item.value
        literal_kind = type(literal).__name__
        fits = {
            "int": ("IntLiteral",),
            "double": ("IntLiteral", "DoubleLiteral"),
            "string": ("StringLiteral",),
            "bool": ("BoolLiteral",),
        }[item.type]
        text = _unquote(literal.text) if literal_kind == "StringLiteral" else literal.text
        if literal_kind not in fits:
            self.sink.error(
                self.loc(literal),
                f"attribute {item.name} is {item.type}, but its default {literal.text} is "
                f"{_LITERAL_KINDS[literal_kind]}",
            )
        else:
            value = canonical_value(item.type, text)
            if value is None:
                self.sink.error(
                    self.loc(literal),
                    f"attribute {item.name}: {literal.text} is not "
                    f"{'an' if str(item.type)[:1] in 'aeiou' else 'a'} {item.type}",
                )
            attribute.value = value
        return attribute

    # -- formulas --------------------------------------------------------------------
    def formula(self, node: Any) -> Any:
        kind = type(node).__name__
        F = self.F
        if kind == "Reference":
            ref = self.locate(F.FeatureRef(), self.loc(node))
            target = self.features.get(node.name)
            if target is None:
                self.sink.error(self.loc(node), f"unknown feature {node.name}")
            else:
                ref.feature = target
            return ref
        if kind == "NotFormula":
            negation = self.locate(F.Not(), self.loc(node))
            negation.operand = self.formula(node.operand)
            return negation
        result = self.formula(node.first)
        if not node.rest:
            return result
        operator = {"Iff": "iff", "Disjunction": "or", "Conjunction": "and"}.get(kind)
        if kind == "Implication":
            # implication-level operators associate to the right: a => b => c is a => (b => c)
            operands = [result] + [self.formula(tail.operand) for tail in node.rest]
            symbols = [tail.operator for tail in node.rest]
            right = operands[-1]
            for index in range(len(symbols) - 1, -1, -1):
                right = self.binary(
                    _IMPLICATION_OPERATORS[symbols[index]], operands[index], right, node.rest[index]
                )
            return right
        if self.balance and operator in ("and", "or"):  # (vocabulary.MAX_FORMULA_DEPTH)
            operands = [result] + [self.formula(tail.operand) for tail in node.rest]
            return balanced(operands, lambda a, b: self.binary(operator, a, b, node))
        for tail in node.rest:
            result = self.binary(cast(str, operator), result, self.formula(tail.operand), tail)
        return result

    def binary(self, operator: str, left: Any, right: Any, node: Any) -> Any:
        formula = self.F.BinaryFormula(operator=operator)
        formula.srcFile, formula.srcLine, formula.srcCol = left.srcFile, left.srcLine, left.srcCol
        formula.left, formula.right = left, right
        return formula


# Attribute names UVL and FeatureIDE use for the feature's own properties; a .fm
# attribute called like this would come back from an export as that property.
_RESERVED_ATTRIBUTES = {
    "abstract": "attribute name abstract is reserved: write 'abstract' before the feature name",
    "sharing": "attribute name sharing is reserved: write 'sharing public|protected|private'",
    "capability": "attribute name capability is reserved: write 'capability KEY [OP VALUE]'",
}
_IMPLICATION_OPERATORS = {"=>": "implies", "requires": "requires", "excludes": "excludes"}
_LITERAL_KINDS = {
    "IntLiteral": "an int",
    "DoubleLiteral": "a double",
    "StringLiteral": "a string",
    "BoolLiteral": "a bool",
}
