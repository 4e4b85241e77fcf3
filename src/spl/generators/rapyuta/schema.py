"""The rce-ros configuration format's JSON Schema, and the problems it finds in one file.

What one file may look like is the schema's; what the engine refuses across a product's
files is :mod:`spl.generators.rapyuta.rules`'. Both report a
:class:`ConfigurationProblem` at the JSON path of the offending entry.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from functools import cache
from importlib.resources import files
from typing import cast

import jsonschema

from spl.generators.json_text import Document


@dataclass(frozen=True, order=True)
class ConfigurationProblem:
    """One refusal: the file, the JSON path of the entry, what is wrong, which rule."""

    file: str
    path: str
    message: str
    rule: str

    def __str__(self) -> str:
        where = f"{self.path}: " if self.path else ""
        return f"{self.file}: {where}{self.message} [{self.rule}]"


@cache
def schema() -> Document:
    """The shipped JSON Schema (draft 2020-12) of the rce-ros configuration format."""
    text = files("spl.generators").joinpath("schemas/rapyuta.schema.json").read_text("utf-8")
    return json.loads(text)


@cache
def validator() -> jsonschema.Draft202012Validator:
    """The schema's validator, built once per process (building one costs as much as a
    check), from a copy of the schema whose local references are replaced by the
    definitions they name: jsonschema looks a ``$ref`` up in its registry at every use,
    most of a check's time. The copy applies the same keywords in the same order, so it
    finds the same errors with the same messages at the same paths (the tests compare
    both on damaged configurations)."""
    document = schema()
    return jsonschema.Draft202012Validator(
        inline_references(document, cast("Mapping[str, object]", document.get("$defs", {}))),
        format_checker=jsonschema.Draft202012Validator.FORMAT_CHECKER,
    )


# Keywords whose values are data, not schemas: nothing in them is a reference.
_DATA_KEYWORDS = frozenset({"$defs", "enum", "const", "examples", "default"})


def inline_references(
    node: object, defs: Mapping[str, object], within: tuple[str, ...] = ()
) -> object:
    """``node`` with every ``{"$ref": "#/$defs/NAME"}`` (nothing else beside it) replaced
    by that definition, itself inlined; a definition that refers to itself, directly or
    not, stays a reference (``$defs`` is kept for it)."""
    if isinstance(node, list):
        return [inline_references(item, defs, within) for item in node]
    if not isinstance(node, dict):
        return node
    ref = node.get("$ref")
    if len(node) == 1 and isinstance(ref, str) and ref.startswith("#/$defs/"):
        name = ref.removeprefix("#/$defs/")
        if name in defs and name not in within and not any(c in name for c in "~/%"):
            return inline_references(defs[name], defs, (*within, name))
        return node
    return {
        key: value if key in _DATA_KEYWORDS else inline_references(value, defs, within)
        for key, value in node.items()
    }


def schema_problems(config: object, name: str) -> list[ConfigurationProblem]:
    """Schema violations of one file, each at its JSON path."""
    problems = [
        ConfigurationProblem(name, json_path(error.absolute_path), error.message, "schema")
        for error in validator().iter_errors(config)
    ]
    return sorted(problems)


def json_path(parts: Iterable[object]) -> str:
    """``connections[2].tagA``: where an entry is, as problems name it."""
    text = ""
    for part in parts:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else str(part))
    return text
