"""Reading UVL (Universal Variability Language) into a plain feature model, in one pass.

The reader follows the reference grammar (uvlparser 2.x: ``UVLLexer.g4``,
``UVLParser.g4`` and its Python lexer, which turns line breaks and indentation into
NEWLINE, INDENT and DEDENT tokens, ignoring line breaks inside brackets): one regular
expression tokenizes the whole file the way the ANTLR lexer does
(:mod:`spl.dsl.interop.uvl_lexer`), and a recursive descent over the grammar's rules builds
:mod:`spl.dsl.fm.plain` objects directly. A file
the reference grammar refuses is refused here too (``tests/test_uvl_conformance.py``
checks both on the same files). The Boolean level is read whole: language levels
(``include``) and composition (``imports``, :mod:`spl.dsl.interop.uvl_imports`), and
attributes of any value (:mod:`spl.dsl.interop.uvl_attributes`). Valid UVL of the other
levels (typed features, feature cardinalities, arithmetic and attribute constraints)
is refused with a located "... is not supported" instead of being silently dropped.

Cost is linear in the file: no per-line token objects, no pyecore; the Linux kernel
model (600 KB) reads in a fraction of a second.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import NoReturn

from spl.core.cyclic_gc import without_cyclic_gc
from spl.core.diagnostics import DiagnosticSink, ModelError, model_text
from spl.dsl import literals
from spl.dsl.fm.plain import (
    Attribute,
    Feature,
    FeatureModel,
    Group,
    Source,
)
from spl.dsl.fm.vocabulary import too_deep
from spl.dsl.interop.interchange import (
    ORIGINAL_NAME,
    FeatureNames,
    model_name,
)
from spl.dsl.interop.uvl_attributes import AttributeReader
from spl.dsl.interop.uvl_formulas import FormulaReader, Syntax
from spl.dsl.interop.uvl_imports import Imported, ImportReader, renamed, splice
from spl.dsl.interop.uvl_lexer import tokenize

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


class UvlReader(FormulaReader, ImportReader, AttributeReader):
    """One UVL text -> one :class:`fm_plain.FeatureModel`; every problem raised at once.
    ``importing``: the files being read around this one (an imported model's reader)."""

    def __init__(self, text: str, filename: str, importing: tuple[str, ...] = ()) -> None:
        text = text.replace("\r\n", "\n").replace("\r", "\n")
        self.source = Source(filename, text)
        self.text = text
        self.importing = importing or (str(Path(filename).resolve()),)
        self.imported: dict[str, Imported] = {}
        self.unread: set[str] = set()
        # alias -> (feature, its identifier in the imported model), for its constraints
        self.spliced: dict[str, list[tuple[Feature, str]]] = {}
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
            if tokens[self.index][0] == "include":
                self.language_levels()
                self.optional_newline()
            if tokens[self.index][0] == "imports":
                self.imports(_read_imported)
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
            self.imported_constraints(model)
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
        original = ".".join(parts)
        spliced = self.placed(parts, position) if len(parts) > 1 else None
        if self.depth > MAX_TREE_DEPTH:
            self.error(
                position,
                f"feature {'.'.join(parts)} is nested {self.depth} levels deep (at most "
                f"{MAX_TREE_DEPTH}): the readers and writers of the tree would run out of stack",
            )
            raise Syntax
        if spliced is not None:  # an imported model's root: its whole tree joins here
            alias, feature = spliced
            tree = splice(alias, feature)
            self.spliced[alias] = [(part, part.name) for part, _ in tree]
            self.features.extend(tree)
        else:
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

    def imported_constraints(self, model: FeatureModel) -> None:
        """The constraints of every imported model placed in the tree, over this model's
        identifiers (docs/fm.md, "Language levels and composition")."""
        for alias, imported in self.imported.items():
            if alias in self.spliced:
                names = {old: feature.name for feature, old in self.spliced[alias]}
                model.constraints.extend(renamed(c, names) for c in imported.model.constraints)


def _read_imported(path: Path, importing: tuple[str, ...]) -> FeatureModel:
    """An imported UVL file, read as a model of its own (its imports beside it)."""
    return UvlReader(model_text(path), str(path), importing).read(path.stem)


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
