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
attributes of any value (:mod:`spl.dsl.interop.uvl_attributes`). So are the Arithmetic
and Type levels: typed features, feature cardinalities, constraints in attributes and
equations (:mod:`spl.dsl.interop.uvl_equations`); a model using them is a
:class:`~spl.dsl.interop.uvl_typed.TypedFeatureModel`.

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
from spl.dsl.interop.uvl_equations import EquationReader
from spl.dsl.interop.uvl_formulas import FormulaReader, Syntax
from spl.dsl.interop.uvl_imports import Imported, ImportReader, renamed, splice
from spl.dsl.interop.uvl_lexer import tokenize
from spl.dsl.interop.uvl_typed import Equation, TypedFeatureModel, renamed_equation

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


class UvlReader(FormulaReader, EquationReader, ImportReader, AttributeReader):
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
        # the Arithmetic and Type levels (docs/fm.md): by original name while reading the
        # tree, by identifier once named
        self.written_types: dict[str, str] = {}
        self.written_cardinalities: dict[str, tuple[int, int, int]] = {}
        self.types: dict[str, str] = {}
        self.cardinalities: dict[str, tuple[int, int, int]] = {}
        self.by_identifier: dict[str, Feature] = {}
        self.equations: list[Equation] = []
        self.attribute_constraints: list[tuple[int, int]] = []  # token ranges, read last
        self.values_of_features: dict[Feature, dict[str, tuple[str, str]]] = {}
        self.written_values: dict[tuple[str, str], tuple[str, str]] = {}

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
                self.imported_types()
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
            self.read_attribute_constraints(model)
            self.imported_constraints(model)
            if tokens[self.index][0] != "EOF":
                self.fail("expected namespace, features or constraints (in that order)")
        except Syntax:
            pass
        self.sink.raise_if_errors()
        if not (self.types or self.cardinalities or self.equations):
            return model
        typed = TypedFeatureModel(model)
        typed.types, typed.cardinalities = self.types, self.cardinalities
        typed.equations = self.equations
        return typed

    def read_attribute_constraints(self, model: FeatureModel) -> None:
        """The constraints written in attributes (``{constraint C}``, ``{constraints [C,
        ...]}``): constraints of the model like any other, read once every feature is
        named (they may name features after theirs)."""
        after = self.index
        for start, end in self.attribute_constraints:
            self.index = start
            constraint = self.constraint_between(end)
            if constraint is not None:
                model.constraints.append(constraint)
        self.index = after

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
        typed = kind if kind in ("String", "Integer", "Real") else None
        if kind in ("String", "Integer", "Real", "Boolean"):
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
        if typed is not None:
            self.written_types[original] = typed
        if tokens[self.index][0] == "cardinality":
            self.index += 1
            _, text, at = self.expect("card", "a cardinality [n..m]")
            lower, upper = _bounds(text)
            if lower is None or upper is None:
                self.error(at, f"bad cardinality {text}: a bound is out of range")
            elif lower < 0 or (upper != -1 and lower > upper):
                self.error(at, f"bad feature cardinality {text}")
            else:
                self.written_cardinalities[original] = (lower, upper, at)
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
            lower, upper = _bounds(text)
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
            self.by_identifier[identifier] = feature
            for attribute, value in self.values_of_features.get(feature, {}).items():
                self.written_values[identifier, attribute] = value
            if original in self.written_types:
                self.types[identifier] = self.written_types[original]
            if original in self.written_cardinalities:
                self.cardinalities[identifier] = self.written_cardinalities[original]
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
                if isinstance(imported.model, TypedFeatureModel):
                    self.equations.extend(
                        Equation(e.source, e.position, renamed_equation(e.formula, names))
                        for e in imported.model.equations
                    )

    def imported_types(self) -> None:
        """The types and feature cardinalities of the imported models placed in the tree,
        under this model's identifiers (before this model's equations name them)."""
        for alias, imported in self.imported.items():
            if alias in self.spliced and isinstance(imported.model, TypedFeatureModel):
                names = {old: feature.name for feature, old in self.spliced[alias]}
                for old, kind in imported.model.types.items():
                    self.types[names[old]] = kind
                for old, bounds in imported.model.cardinalities.items():
                    self.cardinalities[names[old]] = bounds


def _read_imported(path: Path, importing: tuple[str, ...]) -> FeatureModel:
    """An imported UVL file, read as a model of its own (its imports beside it)."""
    return UvlReader(model_text(path), str(path), importing).read(path.stem)


def _bounds(text: str) -> tuple[int | None, int | None]:
    """``[n..m]``, ``[n..*]`` or ``[n]`` as (lower, upper), upper -1 for ``*``; None for a
    bound out of range (EInt in the metamodel)."""
    bounds = text[1:-1].split("..")
    lower = literals.int_literal(bounds[0], literals.INT32_MAX)
    upper = -1 if bounds[-1] == "*" else literals.int_literal(bounds[-1], literals.INT32_MAX)
    return lower, upper


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
