"""UVL (Universal Variability Language) import and export, as flamapy/uvlparser write it.

UVL is indentation-based, so instead of a textX grammar a small tokenizer reads each
line and the indentation nests them (``features`` -> feature -> group keyword ->
feature ...). Supported: ``namespace``, ``features`` with ``mandatory optional
alternative or`` and cardinality groups ``[n..m]`` / ``[n]`` / ``[n..*]``, feature
attributes ``{abstract, key value, ...}`` (string, int, double, bool values; an
attribute ``sharing 'protected'`` becomes the SharingConfig), and ``constraints``
with ``! & | => <=>`` and parentheses. Anything else (imports, typed or cardinality
features, arithmetic constraints) is reported as unsupported, located, instead of
being silently dropped. Names that are not .fm identifiers are renamed as
:mod:`spl.dsl.fm_formats` describes and written back unchanged on export.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass, field
from decimal import Decimal
from pathlib import Path
from typing import Any, ClassVar

from spl.diagnostics import Diagnostic, DiagnosticSink, Location, ModelError, read_source
from spl.dsl import literals
from spl.dsl.fm import SHARING_MODES, canonical_value, too_deep
from spl.dsl.fm_formats import (
    ORIGINAL_NAME,
    FeatureNames,
    exported_attributes,
    model_name,
    original_name,
)
from spl.dsl.fm_printer import format_formula
from spl.metamodels import fm as fm_metamodel

_GROUP_KEYWORDS = {"mandatory", "optional", "alternative", "or"}
# Words a UVL reader treats specially; names spelled like them are quoted on export.
_UVL_KEYWORDS = frozenset(
    {
        "namespace",
        "features",
        "constraints",
        "constraint",
        "imports",
        "include",
        "as",
        "mandatory",
        "optional",
        "alternative",
        "or",
        "cardinality",
        "abstract",
        "true",
        "false",
        "Integer",
        "Boolean",
        "Real",
        "String",
        "sum",
        "avg",
        "len",
        "floor",
        "ceil",
        "Type",
        "Arithmetic",
    }
)
_PLAIN_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
# What the UVL grammar (uvl-parser) accepts unquoted; quoted names exclude . " CR LF.
_UVL_PLAIN_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")

_TOKEN = re.compile(
    r"""
    (?P<space>[ \t]+)
  | (?P<qname>"[^"\n]*")
  | (?P<string>'[^'\n]*')
  | (?P<number>-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?(?![A-Za-z_]))
  | (?P<op><=>|=>|\.\.|[!&|(){}\[\],*])
  | (?P<name>[A-Za-z_][A-Za-z0-9_#§%?.]*)
  | (?P<other>.)
    """,
    re.VERBOSE,
)
_COMMENT_OR_STRING = re.compile(r'"[^"\n]*"|\'[^\'\n]*\'|//[^\n]*|/\*.*?\*/', re.DOTALL)


@dataclass
class _Token:
    kind: str
    text: str
    position: int


@dataclass
class _Line:
    indent: int
    tokens: list[_Token]
    position: int
    children: list[_Line] = field(default_factory=list)


def read_uvl(path: str | Path) -> Any:
    """Import a UVL file as an ``fm.FeatureModel``; raise ModelError with every problem."""
    path = Path(path)
    return parse_uvl(read_source(path), str(path), default_name=path.stem)


def parse_uvl(text: str, filename: str = "<string>", default_name: str = "FeatureModel") -> Any:
    """Import UVL text; ``default_name`` names the model when it has no namespace."""
    try:
        return _Reader(text, filename).read(default_name)
    except RecursionError:
        raise ModelError([too_deep(filename)]) from None


class _Reader:
    def __init__(self, text: str, filename: str) -> None:
        self.text = _blank_comments(text)
        self.filename = filename
        self.sink = DiagnosticSink()
        self.F = fm_metamodel()
        self.line_starts = [0] + [m.end() for m in re.finditer("\n", text)]

    # -- locations -------------------------------------------------------------------
    def loc(self, position: int) -> Location:
        line = bisect.bisect_right(self.line_starts, position)
        return Location(self.filename, line, position - self.line_starts[line - 1] + 1)

    def error(self, position: int, message: str) -> None:
        self.sink.error(self.loc(position), message)

    def locate(self, element: Any, position: int) -> Any:
        where = self.loc(position)
        element.srcFile, element.srcLine, element.srcCol = where.file, where.line, where.col
        return element

    # -- structure -------------------------------------------------------------------
    def lines(self) -> list[_Line]:
        """The non-blank lines nested by indentation (tabs count as 4 columns)."""
        top: list[_Line] = []
        stack: list[_Line] = []
        position = 0
        for raw in self.text.split("\n"):
            start = position
            position += len(raw) + 1
            stripped = raw.lstrip(" \t")
            if not stripped.strip():
                continue
            indent = len(raw[: len(raw) - len(stripped)].expandtabs(4))
            offset = start + len(raw) - len(stripped)
            line = _Line(indent, self.tokenize(stripped.rstrip(), offset), offset)
            while stack and stack[-1].indent >= indent:
                stack.pop()
            (stack[-1].children if stack else top).append(line)
            stack.append(line)
        return top

    def tokenize(self, text: str, offset: int) -> list[_Token]:
        tokens = []
        for match in _TOKEN.finditer(text):
            kind = match.lastgroup or "other"
            if kind != "space":
                tokens.append(_Token(kind, match.group(), offset + match.start()))
        return tokens

    def read(self, default_name: str) -> Any:
        F = self.F
        model = self.locate(F.FeatureModel(name=model_name(default_name)), 0)
        features_line = None
        constraint_lines: list[_Line] = []
        for line in self.lines():
            head = line.tokens[0]
            if head.text == "namespace" and len(line.tokens) == 2:
                model.name = model_name(_unquote(line.tokens[1]))
                if line.children:
                    self.error(
                        line.children[0].position, "unexpected indented line after namespace"
                    )
            elif head.text == "features" and len(line.tokens) == 1:
                if features_line is not None:
                    self.error(head.position, "a second 'features' section")
                features_line = line
            elif head.text == "constraints" and len(line.tokens) == 1:
                constraint_lines.extend(line.children)
            elif head.text in ("imports", "include"):
                self.error(head.position, f"UVL '{head.text}' is not supported")
            else:
                self.error(
                    head.position, f"expected namespace, features or constraints, got {head.text}"
                )
        if features_line is None or not features_line.children:
            self.error(0, "the UVL file has no 'features' section with a root feature")
            self.sink.raise_if_errors()
        roots = features_line.children
        for extra in roots[1:]:
            self.error(extra.position, "a feature model has exactly one root feature")
        declared: list[tuple[_Line, str]] = []
        self.collect_names(roots[0], declared)
        self.names = FeatureNames(name for _, name in declared)
        self.features: dict[str, Any] = {}
        model.root = self.feature(roots[0])
        for line in constraint_lines:
            tokens = list(line.tokens)
            stack = list(line.children)
            while stack:  # a constraint may continue on more indented lines
                more = stack.pop(0)
                tokens.extend(more.tokens)
                stack[:0] = more.children
            formula = _FormulaParser(self, tokens, line.position).parse()
            if formula is not None:
                constraint = self.locate(F.Constraint(), line.position)
                constraint.formula = formula
                model.constraints.append(constraint)
        self.sink.raise_if_errors()
        return model

    def collect_names(self, line: _Line, out: list[tuple[_Line, str]]) -> None:
        stack = [line]
        while stack:
            current = stack.pop()
            name = self.declared_name(current)
            if name is not None:
                out.append((current, name))
            for group in reversed(current.children):
                stack.extend(reversed(group.children))

    def declared_name(self, line: _Line) -> str | None:
        tokens = line.tokens
        if tokens[0].text in ("Boolean",) and len(tokens) > 1:
            tokens = tokens[1:]
        if tokens[0].kind in ("name", "qname") and tokens[0].text not in _GROUP_KEYWORDS:
            return _unquote(tokens[0])
        return None

    def feature(self, line: _Line) -> Any:
        F = self.F
        tokens = line.tokens
        if tokens[0].text == "Boolean" and len(tokens) > 1:
            tokens = tokens[1:]
        elif tokens[0].text in ("Integer", "Real", "String"):
            self.error(tokens[0].position, f"typed feature ({tokens[0].text}) is not supported")
            tokens = tokens[1:] or tokens
        head = tokens[0]
        if head.kind not in ("name", "qname") or head.text in _GROUP_KEYWORDS:
            self.error(head.position, f"expected a feature name, got {head.text}")
            return self.locate(F.Feature(name="_"), head.position)
        original = _unquote(head)
        identifier = self.names[original]
        feature = self.locate(F.Feature(name=identifier), head.position)
        if original in self.features:
            self.error(head.position, f"duplicate feature {original}")
        else:
            self.features[original] = feature
        if identifier != original:
            attribute = self.locate(F.Attribute(name=ORIGINAL_NAME, value=original), head.position)
            attribute.type = F.AttributeType.string
            feature.attributes.append(attribute)
        rest = tokens[1:]
        if rest and rest[0].text == "cardinality":
            self.error(rest[0].position, "feature cardinalities are not supported")
            return feature
        if rest and rest[0].text == "{":
            rest = self.attributes(feature, rest)
        if rest:
            self.error(rest[0].position, f"unexpected {rest[0].text} after feature {original}")
        for group_line in line.children:
            group = self.group(group_line)
            if group is not None:
                feature.groups.append(group)
        return feature

    def attributes(self, feature: Any, tokens: list[_Token]) -> list[_Token]:
        """Read ``{key value, ...}`` into the feature; return the tokens after ``}``."""
        F = self.F
        index = 1
        seen: set[str] = set()
        while index < len(tokens) and tokens[index].text != "}":
            key = tokens[index]
            name = _unquote(key)
            if key.kind not in ("name", "qname") or not _PLAIN_NAME.match(name):
                self.error(key.position, f"expected an attribute name, got {key.text}")
                return []
            index += 1
            value: _Token | None = None
            if index < len(tokens) and tokens[index].text not in (",", "}"):
                value = tokens[index]
                index += 1
            if index < len(tokens) and tokens[index].text == ",":
                index += 1
            if name in seen:
                self.error(key.position, f"attribute {name} given twice")
                continue
            seen.add(name)
            if name == "abstract":
                if value is not None and value.text not in ("true", "false"):
                    self.error(value.position, "abstract takes true or false")
                feature.abstract = value is None or value.text == "true"
                continue
            if name == ORIGINAL_NAME:
                self.error(key.position, f"attribute name {ORIGINAL_NAME} is reserved")
                continue
            type_name, text = self.attribute_value(value)
            if type_name is None:
                continue
            if name == "sharing":
                if (
                    type_name != "string"
                    or text not in SHARING_MODES
                    or feature.sharing is not None
                ):
                    self.error(
                        (value or key).position,
                        f"sharing must be one of {', '.join(SHARING_MODES)}",
                    )
                    continue
                config = self.locate(F.SharingConfig(), key.position)
                config.mode = F.SharingMode.getEEnumLiteral(text)
                feature.sharing = config
                continue
            canonical = canonical_value(type_name, text)
            if canonical is None:  # a number out of range (1e999, a 30-digit int)
                self.error(value.position, f"attribute {name}: {text} is out of range")
                continue
            attribute = self.locate(F.Attribute(name=name), key.position)
            attribute.type = F.AttributeType.getEEnumLiteral(type_name)
            attribute.value = canonical
            feature.attributes.append(attribute)
        if index >= len(tokens):
            self.error(tokens[0].position, "attribute list is not closed with }")
            return []
        return tokens[index + 1 :]

    def attribute_value(self, value: _Token | None) -> tuple[str | None, str]:
        if value is None:
            return "bool", "true"
        if value.text in ("true", "false"):
            return "bool", value.text
        if value.kind == "string":
            return "string", value.text[1:-1]
        if value.kind == "number":
            return ("double" if re.search(r"[.eE]", value.text) else "int"), value.text
        self.error(value.position, f"unsupported attribute value {value.text}")
        return None, ""

    def group(self, line: _Line) -> Any:
        F = self.F
        tokens = line.tokens
        head = tokens[0]
        group = self.locate(F.Group(), head.position)
        if head.text in _GROUP_KEYWORDS and len(tokens) == 1:
            group.kind = F.GroupKind.getEEnumLiteral(
                "alternative" if head.text == "alternative" else head.text
            )
        elif head.text == "[" or (head.text == "cardinality" and len(tokens) > 1):
            bounds = tokens[1:] if head.text == "cardinality" else tokens
            parsed = _cardinality(bounds)
            if parsed is None:
                self.error(head.position, "expected a group cardinality [n..m], [n] or [n..*]")
                return None
            group.kind = F.GroupKind.cardinality
            group.lower, group.upper = parsed
            if group.upper == 0 or (group.upper != -1 and group.lower > group.upper):
                self.error(head.position, f"bad cardinality [{group.lower}..{group.upper}]")
        else:
            self.error(
                head.position,
                f"expected a group (mandatory, optional, alternative, or, [n..m]), got {head.text}",
            )
            return None
        if not line.children:
            self.error(head.position, f"group {head.text} has no features")
        for child in line.children:
            group.features.append(self.feature(child))
        return group


def _cardinality(tokens: list[_Token]) -> tuple[int, int] | None:
    texts = [t.text for t in tokens]
    bound = literals.INT32_MAX
    if len(texts) == 3 and texts[0] == "[" and texts[2] == "]":
        lower = literals.int_literal(texts[1], bound) if texts[1].isdigit() else None
        return (lower, lower) if lower is not None else None
    if len(texts) == 5 and (texts[0], texts[2], texts[4]) == ("[", "..", "]"):
        lower = literals.int_literal(texts[1], bound) if texts[1].isdigit() else None
        upper = -1 if texts[3] == "*" else literals.int_literal(texts[3], bound)
        if lower is not None and upper is not None and not texts[3].startswith(("+", "-")):
            return lower, upper
    return None


class _FormulaParser:
    """Precedence climbing over one constraint: ! > & > | > => > <=> (left-associative)."""

    _BINARY: ClassVar[dict[str, tuple[str, int]]] = {
        "<=>": ("iff", 0),
        "=>": ("implies", 1),
        "|": ("or", 2),
        "&": ("and", 3),
    }

    def __init__(self, reader: _Reader, tokens: list[_Token], position: int) -> None:
        self.reader = reader
        self.tokens = tokens
        self.index = 0
        self.position = position
        self.failed = False

    def parse(self) -> Any:
        formula = self.binary(0)
        if not self.failed and self.index < len(self.tokens):
            self.fail(self.tokens[self.index], "expected an operator (! & | => <=>)")
        return None if self.failed else formula

    def fail(self, token: _Token | None, message: str) -> None:
        if not self.failed:
            where = token.position if token is not None else self.position
            found = f", got {token.text}" if token is not None else " at the end of the constraint"
            self.reader.error(where, f"{message}{found}")
        self.failed = True

    def peek(self) -> _Token | None:
        return self.tokens[self.index] if self.index < len(self.tokens) else None

    def binary(self, level: int) -> Any:
        if level > 3:
            return self.unary()
        left = self.binary(level + 1)
        while not self.failed:
            token = self.peek()
            entry = self._BINARY.get(token.text) if token is not None else None
            if entry is None or entry[1] != level:
                break
            self.index += 1
            right = self.binary(level + 1)
            formula = self.reader.F.BinaryFormula(operator=entry[0])
            self.reader.locate(formula, token.position)
            formula.left, formula.right = left, right
            left = formula
        return left

    def unary(self) -> Any:
        F = self.reader.F
        token = self.peek()
        if token is None:
            self.fail(None, "expected a feature, ! or (")
            return None
        if token.text == "!":
            self.index += 1
            negation = self.reader.locate(F.Not(), token.position)
            negation.operand = self.unary()
            return negation
        if token.text == "(":
            self.index += 1
            inner = self.binary(0)
            closing = self.peek()
            if closing is None or closing.text != ")":
                self.fail(closing, "expected )")
            self.index += 1
            return inner
        if token.kind in ("name", "qname") and token.text not in ("true", "false"):
            self.index += 1
            name = _unquote(token)
            reference = self.reader.locate(F.FeatureRef(), token.position)
            target = self.reader.features.get(name)
            if target is None:
                self.reader.error(token.position, f"unknown feature {name}")
            else:
                reference.feature = target
            follower = self.peek()
            if follower is not None and follower.kind == "other":
                self.fail(follower, "arithmetic and attribute constraints are not supported")
            return reference
        self.fail(token, "expected a feature, ! or (")
        return None


def _unquote(token: _Token) -> str:
    return token.text[1:-1] if token.kind == "qname" else token.text


def _blank_comments(text: str) -> str:
    """Comments replaced by spaces (newlines kept), so positions stay those of the file."""

    def blank(match: re.Match[str]) -> str:
        found = match.group()
        if found.startswith(("//", "/*")):
            return re.sub(r"[^\n]", " ", found)
        return found

    return _COMMENT_OR_STRING.sub(blank, text)


# -- export ---------------------------------------------------------------------------
_UVL_SYMBOLS = {
    "iff": "<=>",
    "implies": "=>",
    "or": "|",
    "and": "&",
    "not": "!",
}


def write_uvl(model: Any) -> str:
    """The model as UVL text (tab-indented, as flamapy writes it).

    ``requires`` becomes ``=>`` and ``A excludes B`` becomes ``A => !B``: UVL has no
    such operators, and the formulas mean the same.
    """
    problems: list[Diagnostic] = []
    lines = [f"namespace {_uvl_id(model.name)}", "", "features"]
    _write_feature(model.root, 1, lines, problems)
    if model.constraints:
        lines.append("")
        lines.append("constraints")
        for constraint in model.constraints:
            formula = _without_requires_excludes(constraint.formula)
            lines.append(
                "\t"
                + format_formula(
                    formula,
                    name_of=lambda f: _uvl_name(f, problems),
                    symbols=_UVL_SYMBOLS,
                    right_assoc_implication=False,
                )
            )
    if problems:
        raise ModelError(problems)
    return "\n".join(lines) + "\n"


def _uvl_name(feature: Any, problems: list[Diagnostic]) -> str:
    name = original_name(feature)
    if _UVL_PLAIN_NAME.match(name) and name not in _UVL_KEYWORDS:
        return name
    if any(c in name for c in '."\r\n'):
        problems.append(
            Diagnostic(
                _where(feature),
                f"feature name {name!r} cannot be written in UVL (a quoted UVL name holds "
                "no '.', '\"' or line break): rename the feature",
            )
        )
    return f'"{name}"'


def _uvl_id(identifier: str) -> str:
    """An identifier (model or attribute name) as a UVL id, quoted when UVL needs it."""
    if _UVL_PLAIN_NAME.match(identifier) and identifier not in _UVL_KEYWORDS:
        return identifier
    return f'"{identifier}"'


def _where(element: Any) -> Location | None:
    if not getattr(element, "srcFile", None):
        return None
    return Location(element.srcFile, element.srcLine or 0, element.srcCol or 0)


def _write_feature(feature: Any, depth: int, lines: list[str], problems: list[Diagnostic]) -> None:
    entries = []
    if feature.abstract:
        entries.append("abstract")
    for attribute in exported_attributes(feature):
        value = attribute.value or ""
        if attribute.type.name == "string":
            if "'" in value or "\n" in value or "\r" in value:
                problems.append(
                    Diagnostic(
                        _where(attribute),
                        f"attribute {attribute.name} of {feature.name}: "
                        f"{value!r} cannot be written as a UVL string",
                    )
                )
            value = f"'{value}'"
        elif attribute.type.name == "double":
            value = _uvl_float(value)
        entries.append(f"{_uvl_id(attribute.name)} {value}")
    if feature.sharing is not None:
        entries.append(f"sharing '{feature.sharing.mode.name}'")
    text = _uvl_name(feature, problems)
    if entries:
        text += " {" + ", ".join(entries) + "}"
    lines.append("\t" * depth + text)
    for group in feature.groups:
        kind = group.kind.name
        if kind == "cardinality":
            upper = "*" if group.upper == -1 else str(group.upper)
            keyword = f"[{group.lower}..{upper}]"
        else:
            keyword = kind
        lines.append("\t" * (depth + 1) + keyword)
        for child in group.features:
            _write_feature(child, depth + 2, lines, problems)


def _uvl_float(canonical: str) -> str:
    """A double as UVL's FLOAT token (digits, a dot, digits: no exponent)."""
    text = format(Decimal(canonical), "f")
    return text if "." in text else text + ".0"


def _without_requires_excludes(formula: Any) -> Any:
    """A copy of the formula using only and/or/not/implies/iff."""
    F = fm_metamodel()
    kind = formula.eClass.name
    if kind == "FeatureRef":
        return F.FeatureRef(feature=formula.feature)
    if kind == "Not":
        return F.Not(operand=_without_requires_excludes(formula.operand))
    left = _without_requires_excludes(formula.left)
    right = _without_requires_excludes(formula.right)
    if formula.operator == "requires":
        return F.BinaryFormula(operator="implies", left=left, right=right)
    if formula.operator == "excludes":
        return F.BinaryFormula(operator="implies", left=left, right=F.Not(operand=right))
    return F.BinaryFormula(operator=formula.operator, left=left, right=right)
