"""Attributes of a UVL feature (``{key value, ...}``), for the UVL reader.

A mixin of :class:`spl.dsl.interop.uvl_reader.UvlReader`, which owns the tokens, the
position and the diagnostics. A value spl's typed attributes hold (a boolean, a number,
a string) becomes an attribute of that type; one they cannot hold (a nested ``{...}``
or vector ``[...]`` value, a name that is not an identifier) is kept as written
(``UVL_ATTRIBUTES``, :mod:`spl.dsl.interop.interchange`) and written back verbatim:
attributes take no part in Boolean analysis (docs/fm.md, "Language levels and
composition"). A constraint written in the attributes, at any depth of a nested value,
is a constraint of the model.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import NoReturn, cast

from spl.dsl.fm.plain import Attribute, Feature, Sharing, Source
from spl.dsl.fm.vocabulary import SHARING_MODES, canonical_value
from spl.dsl.interop.interchange import CAPABILITY, ORIGINAL_NAME, UVL_ATTRIBUTES
from spl.dsl.interop.uvl_formulas import Syntax
from spl.dsl.interop.uvl_lexer import OPENING

_NAMES = ("id", "qid")
_PLAIN_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


class AttributeReader:
    """The ``attributes`` rule; the reader class provides the state named below."""

    tokens: list[tuple[str, str, int]]
    index: int
    text: str
    source: Source
    error: Callable[[int, str], None]
    fail: Callable[[str], NoReturn]
    expect: Callable[[str, str], tuple[str, str, int]]
    attribute_constraints: list[tuple[int, int]]
    values_of_features: dict[Feature, dict[str, tuple[str, str]]]

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
            self.constraint_attribute(kind)
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
            kept = self.nested_value()
            self.keep_as_written(feature, position, self.text[position : value[2]] + kept)
            return
        elif value[0] in _NAMES:  # a word where a value would be: not UVL
            what = "abstract takes true or false" if name == "abstract" else "expected a value"
            self.error(value[2], f"{what} (true, false, a number or a 'string'), got {value[1]}")
            raise Syntax
        else:
            value = None
        if not _PLAIN_NAME.match(name):
            self.keep_as_written(feature, position)
            if value is not None and value[0] in ("int", "float", "string"):
                type_name, literal = _typed(value)  # for equations to read (docs/fm.md)
                self.values_of_features.setdefault(feature, {})[name] = (type_name, literal)
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
        if name in (ORIGINAL_NAME, UVL_ATTRIBUTES):
            self.error(position, f"attribute name {name} is reserved")
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

    def constraint_attribute(self, kind: str) -> None:
        """``constraint C`` or ``constraints [C, ...]``: each constraint's tokens kept,
        read with the model's constraints (``UvlReader.read_attribute_constraints``)."""
        self.index += 1
        if kind == "constraint":
            start = self.index
            self.skip_value()
            self.attribute_constraints.append((start, self.index))
            return
        self.expect("[", "'[' opening the list of constraints")
        if self.tokens[self.index][0] != "]":  # the grammar allows an empty list
            while True:
                start = self.index
                depth = 0
                while True:
                    token = self.tokens[self.index][0]
                    if token == "EOF" or (depth == 0 and token in (",", "]")):
                        break
                    depth += OPENING.get(token, 0)
                    self.index += 1
                self.attribute_constraints.append((start, self.index))
                if self.tokens[self.index][0] != ",":
                    break
                self.index += 1
        self.expect("]", "',' or ']' in the list of constraints")

    def keep_as_written(self, feature: Feature, start: int, written: str | None = None) -> None:
        """The attribute read from ``start`` to the last token taken, kept as its text
        (``UVL_ATTRIBUTES``, :mod:`spl.dsl.interop.interchange`), or as ``written``: that
        text less the constraints read out of its nested values."""
        if written is None:
            written = self.text[start : self.end_of_last_token()]
        for attribute in feature.attributes:
            if attribute.name == UVL_ATTRIBUTES:
                attribute.value += ", " + written
                return
        feature.attributes.append(Attribute(self.source, start, UVL_ATTRIBUTES, "string", written))

    def end_of_last_token(self) -> int:
        _, text, at = self.tokens[self.index - 1]
        return at + len(text)

    def nested_value(self) -> str:
        """Past one ``value`` of the grammar, checked: a literal, ``{attribute, ...}``
        or ``[value, ...]``; the value as kept. A ``constraint`` or ``constraints``
        entry of a nested ``{...}`` is a constraint of the model, as one written
        directly in the feature's attributes is (the grammar's ``attribute`` rule holds
        both; docs/fm.md, "Attributes kept as written"): it is read with the model's
        constraints and left out of the kept text, so a written-back model holds it once."""
        tokens = self.tokens
        kind, text, start = tokens[self.index]
        if kind in ("bool", "int", "float", "string"):
            self.index += 1
            return text
        if kind not in ("{", "["):
            self.fail("expected a value (true, false, a number, a 'string', {...} or [...])")
        close = "}" if kind == "{" else "]"
        self.index += 1
        entries: list[tuple[str, str] | None] = []
        if tokens[self.index][0] != close:
            entries.append(self.nested_entry(kind))
            while tokens[self.index][0] == ",":
                self.index += 1
                entries.append(self.nested_entry(kind))
        self.expect(close, f"',' or '{close}'")
        if all(entry is not None and entry[0] == entry[1] for entry in entries):
            return self.text[start : self.end_of_last_token()]
        return kind + ", ".join(entry[1] for entry in entries if entry is not None) + close

    def nested_entry(self, opening: str) -> tuple[str, str] | None:
        """One attribute of a nested ``{...}`` (``key value?``), or one value of a
        vector: (its text, its text as kept); None for a constraint entry, read as a
        constraint of the model (:meth:`nested_value`)."""
        kind, _, position = self.tokens[self.index]
        if opening == "[":
            kept = self.nested_value()
            return self.text[position : self.end_of_last_token()], kept
        if kind in ("constraint", "constraints"):
            self.constraint_attribute(kind)
            return None
        if kind not in _NAMES:
            self.fail("expected an attribute name")
        self.index += 1
        value = self.tokens[self.index]
        if value[0] not in ("bool", "int", "float", "string", "{", "["):
            written = self.text[position : self.end_of_last_token()]
            return written, written
        kept = self.nested_value()
        return self.text[position : self.end_of_last_token()], self.text[position : value[2]] + kept

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
