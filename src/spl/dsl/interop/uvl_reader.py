"""Reading UVL (Universal Variability Language) into a plain feature model, in one pass.

The reader follows the reference grammar (uvlparser 2.x: ``UVLLexer.g4``,
``UVLParser.g4`` and its Python lexer, which turns line breaks and indentation into
NEWLINE, INDENT and DEDENT tokens, ignoring line breaks inside brackets): one regular
expression tokenizes the whole file the way the ANTLR lexer does
(:mod:`spl.dsl.interop.uvl_lexer`), and a recursive descent over the grammar's rules builds
:mod:`spl.dsl.fm.plain` objects directly. A file
the reference grammar refuses is refused here too (``tests/test_uvl_conformance.py``
checks both on the same files). Valid UVL that spl cannot represent (typed or
cardinality features, imports and includes, dotted references, arithmetic and
attribute constraints, nested or vector attribute values) is refused with a located
"... is not supported" instead of being silently dropped.

Cost is linear in the file: no per-line token objects, no pyecore; the Linux kernel
model (600 KB) reads in a fraction of a second.
"""

from __future__ import annotations

import re
from typing import NoReturn, cast

from spl.core.cyclic_gc import without_cyclic_gc
from spl.core.diagnostics import DiagnosticSink, ModelError
from spl.dsl import literals
from spl.dsl.fm.plain import (
    Attribute,
    Feature,
    FeatureModel,
    Group,
    Sharing,
    Source,
)
from spl.dsl.fm.vocabulary import SHARING_MODES, canonical_value, too_deep
from spl.dsl.interop.interchange import CAPABILITY, ORIGINAL_NAME, FeatureNames, model_name
from spl.dsl.interop.uvl_formulas import FormulaReader, Syntax
from spl.dsl.interop.uvl_lexer import OPENING, tokenize

_GROUPS = ("or", "alternative", "optional", "mandatory")
_NAMES = ("id", "qid")
_UNCLOSED = {
    '"': "a quoted name is closed on its line and holds no '.'",
    "'": "a string is closed on its line and is not empty",
}
_PLAIN_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
# Features nested deeper are refused, located (docs/fm.md, "Limits"): the tree's readers
# and writers recurse once or twice a level. The deepest of the community models spl
# is measured on (automotive01) is 13 levels.
MAX_TREE_DEPTH = 300


class UvlReader(FormulaReader):
    """One UVL text -> one :class:`fm_plain.FeatureModel`; every problem raised at once."""

    def __init__(self, text: str, filename: str) -> None:
        text = text.replace("\r\n", "\n").replace("\r", "\n")
        self.source = Source(filename, text)
        self.sink = DiagnosticSink()
        self.tokens = tokenize(text)
        self.index = 0
        self.features: list[tuple[Feature, str]] = []  # (feature, original name), pre-order
        self.identifiers: dict[str, str] = {}
        self.failed_names = False  # the constraint being read names an unknown feature
        self.depth = 0  # features open around the one being read

    # -- plumbing --------------------------------------------------------------------
    def error(self, position: int, message: str) -> None:
        self.sink.error(self.source.location(position), message)

    def fail(self, message: str) -> NoReturn:
        kind, text, position = self.tokens[self.index]
        self.error(position, f"{message}, got {_shown(kind, text)}")
        raise Syntax

    def expect(self, kind: str, what: str) -> tuple[str, str, int]:
        token = self.tokens[self.index]
        if token[0] != kind:
            self.fail(f"expected {what}")
        self.index += 1
        return token

    def skip_block(self) -> None:
        """Past the indented block that follows (imports, include)."""
        if self.tokens[self.index][0] == "NL":
            self.index += 1
        if self.tokens[self.index][0] != "INDENT":
            return
        depth = 0
        while True:
            kind = self.tokens[self.index][0]
            self.index += 1
            depth += (kind == "INDENT") - (kind == "DEDENT")
            if depth == 0 or kind == "EOF":
                return

    # -- featureModel ----------------------------------------------------------------
    def read(self, default_name: str) -> FeatureModel:
        model = FeatureModel(self.source, model_name(default_name), default_name)
        tokens = self.tokens
        bad = next((token for token in tokens if token[0] == "bad"), None)
        if bad is not None:  # the lexer refuses the file: nothing after it is read
            self.error(bad[2], _UNCLOSED.get(bad[1], f"unexpected character {bad[1]!r}"))
            self.sink.raise_if_errors()
        try:
            if tokens[self.index][0] == "namespace":
                self.index += 1
                model.written_name = ".".join(self.reference()[0])
                model.name = model_name(model.written_name)
            self.optional_newline()
            for keyword in ("include", "imports"):
                if tokens[self.index][0] == keyword:
                    self.error(tokens[self.index][2], f"UVL '{keyword}' is not supported")
                    self.index += 1
                    self.skip_block()
                    self.optional_newline()
            if tokens[self.index][0] == "features":
                self.index += 1
                self.expect("NL", "a line break after 'features'")
                self.expect("INDENT", "the root feature, indented")
                model.root = self.feature()
                self.expect("DEDENT", "one root feature (a model has exactly one)")
                self.optional_newline()
                self.name_features()
            elif tokens[self.index][0] == "EOF":
                self.error(
                    tokens[self.index][2],
                    "a UVL model without a 'features' section is not supported "
                    "(spl needs a root feature)",
                )
            elif tokens[self.index][0] == "namespace":
                self.fail("namespace comes first (not even a comment line before it)")
            else:
                self.fail("expected the 'features' section")
            if tokens[self.index][0] == "constraints":
                self.index += 1
                self.expect("NL", "a line break after 'constraints'")
                self.expect("INDENT", "constraints, indented")
                while tokens[self.index][0] not in ("DEDENT", "EOF"):
                    if tokens[self.index][0] == "INDENT":
                        self.error(
                            tokens[self.index][2],
                            "unexpected indentation: a constraint continues on another line "
                            "only inside parentheses",
                        )
                        self.skip_block()
                        continue
                    constraint = self.constraint_line()
                    if constraint is not None:
                        model.constraints.append(constraint)
                self.expect("DEDENT", "the end of the constraints")
            if tokens[self.index][0] != "EOF":
                self.fail("expected namespace, features or constraints (in that order)")
        except Syntax:
            pass
        self.sink.raise_if_errors()
        return model

    def optional_newline(self) -> None:
        if self.tokens[self.index][0] == "NL":
            self.index += 1

    def reference(self) -> tuple[list[str], int]:
        """``(id DOT)* id``: the parts unquoted, and where the reference starts."""
        kind, text, position = self.tokens[self.index]
        if kind not in _NAMES:
            self.fail("expected a name")
        parts = [text[1:-1] if kind == "qid" else text]
        self.index += 1
        while self.tokens[self.index][0] == ".":
            self.index += 1
            kind, text, _ = self.tokens[self.index]
            if kind not in _NAMES:
                self.fail("expected a name after '.'")
            parts.append(text[1:-1] if kind == "qid" else text)
            self.index += 1
        return parts, position

    # -- features --------------------------------------------------------------------
    def feature(self) -> Feature:
        """``featureType? reference featureCardinality? attributes? NEWLINE
        (INDENT group+ DEDENT)?``"""
        tokens = self.tokens
        kind, text, position = tokens[self.index]
        if kind in ("String", "Integer", "Real"):
            self.error(position, f"typed feature ({text}) is not supported")
            self.index += 1
        elif kind == "Boolean":
            self.index += 1
        if tokens[self.index][0] not in _NAMES:
            self.fail("expected a feature name")
        parts, position = self.reference()
        self.depth += 1
        if self.depth > MAX_TREE_DEPTH:
            self.error(
                position,
                f"feature {'.'.join(parts)} is nested {self.depth} levels deep (at most "
                f"{MAX_TREE_DEPTH}): the readers and writers of the tree would run out of stack",
            )
            raise Syntax
        if len(parts) > 1:
            self.error(position, "a dotted feature name (an imported feature) is not supported")
        original = ".".join(parts)
        feature = Feature(self.source, position, original)
        self.features.append((feature, original))
        if tokens[self.index][0] == "cardinality":
            self.error(tokens[self.index][2], "feature cardinalities are not supported")
            self.index += 1
            self.expect("card", "a cardinality [n..m]")
        if tokens[self.index][0] == "{":
            self.attributes(feature)
        self.expect("NL", f"a line break after feature {original}")
        if tokens[self.index][0] == "INDENT":
            self.index += 1
            while True:
                feature.groups.append(self.group())
                if tokens[self.index][0] == "DEDENT":
                    self.index += 1
                    break
        self.depth -= 1
        return feature

    def group(self) -> Group:
        kind, text, position = self.tokens[self.index]
        if kind in _GROUPS:
            group = Group(self.source, position, kind)
        elif kind == "card":
            group = Group(self.source, position, "cardinality")
            bounds = text[1:-1].split("..")
            lower = literals.int_literal(bounds[0], literals.INT32_MAX)
            upper = (
                -1 if bounds[-1] == "*" else literals.int_literal(bounds[-1], literals.INT32_MAX)
            )
            if lower is None or upper is None:  # EInt in the metamodel
                self.error(position, f"bad cardinality {text}: a bound is out of range")
                lower, upper = 0, -1
            elif lower < 0 or upper == 0 or (upper != -1 and lower > upper):
                self.error(position, f"bad cardinality [{lower}..{upper}]")
            group.lower, group.upper = lower, upper
        else:
            self.fail("expected a group (mandatory, optional, alternative, or, [n..m])")
        self.index += 1
        self.expect("NL", f"a line break after group {text}")
        if self.tokens[self.index][0] != "INDENT":
            self.error(position, f"group {text} has no features")
            raise Syntax
        self.index += 1
        while self.tokens[self.index][0] != "DEDENT":
            group.features.append(self.feature())
        self.index += 1
        return group

    def name_features(self) -> None:
        """Identifiers for every feature (:class:`FeatureNames`: injective, in pre-order),
        the original name kept as an attribute where it differs."""
        names = FeatureNames(original for _, original in self.features)
        identifiers = self.identifiers
        for feature, original in self.features:
            if original in identifiers:
                self.error(feature.position, f"duplicate feature {original}")
                continue
            identifier = names[original]
            identifiers[original] = identifier
            feature.name = identifier
            if identifier != original:
                feature.attributes.insert(
                    0, Attribute(self.source, feature.position, ORIGINAL_NAME, "string", original)
                )

    # -- attributes ------------------------------------------------------------------
    def attributes(self, feature: Feature) -> None:
        """``{ (attribute (, attribute)*)? }`` read into the feature."""
        self.index += 1
        seen: set[str] = set()
        if self.tokens[self.index][0] != "}":
            self.attribute(feature, seen)
            while self.tokens[self.index][0] == ",":
                self.index += 1
                self.attribute(feature, seen)
        self.expect("}", "',' or '}' in the attribute list")

    def attribute(self, feature: Feature, seen: set[str]) -> None:
        tokens = self.tokens
        kind, text, position = tokens[self.index]
        if kind in ("constraint", "constraints"):
            self.error(position, "attribute constraints are not supported")
            self.skip_value()
            return
        if kind not in _NAMES:
            self.fail("expected an attribute name")
        self.index += 1
        name = text[1:-1] if kind == "qid" else text
        value: tuple[str, str, int] | None  # None: no value written
        value = tokens[self.index]
        if value[0] in ("bool", "int", "float", "string"):
            self.index += 1
        elif value[0] in ("{", "["):
            self.error(value[2], "nested and vector attribute values are not supported")
            self.skip_value()
            return
        elif value[0] in _NAMES:  # a word where a value would be: not UVL
            what = "abstract takes true or false" if name == "abstract" else "expected a value"
            self.error(value[2], f"{what} (true, false, a number or a 'string'), got {value[1]}")
            raise Syntax
        else:
            value = None
        if not _PLAIN_NAME.match(name):
            self.error(position, f"attribute name {text} is not supported (use an identifier)")
            return
        if name in seen:
            self.error(position, f"attribute {name} given twice")
            return
        seen.add(name)
        if name == "abstract":
            if value is not None and value[0] != "bool":
                self.error(value[2], "abstract takes true or false")
            feature.abstract = value is None or value[1] == "true"
            return
        if name == ORIGINAL_NAME:
            self.error(position, f"attribute name {ORIGINAL_NAME} is reserved")
            return
        type_name, literal = _typed(value)
        if name == "sharing":
            if type_name != "string" or literal not in SHARING_MODES or feature.sharing:
                where = value[2] if value is not None else position
                self.error(where, f"sharing must be one of {', '.join(SHARING_MODES)}")
                return
            feature.sharing = Sharing(self.source, position, literal)
            return
        if name == CAPABILITY:  # read with the .fm condition grammar when turned into EMF
            feature.capability = (type_name, literal, position)
            return
        canonical = canonical_value(type_name, literal)
        if canonical is None:  # a number out of range (1e999, a 30-digit int)
            written = cast("tuple[str, str, int]", value)  # a literal out of range: written
            self.error(written[2], f"attribute {name}: {literal} is out of range")
            return
        feature.attributes.append(Attribute(self.source, position, name, type_name, canonical))

    def skip_value(self) -> None:
        """Past one attribute whose content is not read (to the next ',' or '}')."""
        depth = 0
        while True:
            kind = self.tokens[self.index][0]
            if kind == "EOF" or (depth == 0 and kind in (",", "}")):
                return
            depth += OPENING.get(kind, 0)
            self.index += 1


def _typed(value: tuple[str, str, int] | None) -> tuple[str, str]:
    """An attribute value token as (attribute type, text)."""
    if value is None:
        return "bool", "true"
    kind, text, _ = value
    if kind == "string":
        return "string", text[1:-1]
    return {"bool": "bool", "int": "int", "float": "double"}[kind], text


def _shown(kind: str, text: str) -> str:
    if kind == "NL":
        return "a line break"
    if kind in ("INDENT", "DEDENT"):
        return "a change of indentation"
    if kind == "EOF":
        return "the end of the file"
    return text


def parse_uvl_plain(
    text: str, filename: str = "<string>", default_name: str = "FeatureModel"
) -> FeatureModel:
    """UVL text as a plain feature model; ``default_name`` names it when it has no
    namespace. Raises ModelError with every problem, located."""
    try:
        with without_cyclic_gc():
            return UvlReader(text, filename).read(default_name)
    except RecursionError:
        raise ModelError([too_deep(filename)]) from None
