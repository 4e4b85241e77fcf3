"""The YAML text of Kubernetes documents, written directly for the shapes they have.

A product's manifests are block mappings and sequences of short names, labels, images,
numbers and booleans, plus literal blocks (the launch files and bridge configurations a
ConfigMap carries). For documents made only of such values, this module writes the text
PyYAML's emitter writes (``sort_keys=False``, block style, indent 2, width 2**16, no
unicode), byte for byte, without building nodes and events and calling back into Python
for every scalar's tag (half of generating a product's Kubernetes folder). Anything else
(a string that would need quotes other than the ones a number-like name gets, a key too
long to be a simple key, a scalar at the root, a literal inside a sequence) makes
:func:`block_yaml` return None, and the caller asks PyYAML. tests/test_kubernetes_yaml.py
compares the two on every shipped product and on generated documents.
"""

from __future__ import annotations

import re
from typing import cast

import yaml

from spl.generators.json_text import Document

# A string PyYAML writes plain when its implicit tag is str (and single-quoted, as it
# is, when not): words of printable ASCII separated by single spaces or by colons inside
# a word; the first starting with a letter, digit, ``_`` or ``/`` (or ``-`` or ``--`` before
# one of those: a command's option), no word after a space starting with ``#``. Nothing in it is
# an indicator where it stands, a special character or a line break (the analysis of
# PyYAML's Emitter.analyze_scalar), and it is short enough never to be folded.
_WORD = r"[!-9;-~]"  # printable ASCII but the space and the colon
_SIMPLE = re.compile(rf"(?:[A-Za-z0-9_/]|--?(?=[A-Za-z0-9_])){_WORD}*(?:(?::|[ ](?!#)){_WORD}+)*")
_LONGEST = 1000
_SIMPLE_KEY = 128  # PyYAML writes a longer key as a complex key ("? ...")
# A literal block PyYAML writes as "|" (no indicators): printable ASCII lines, the last
# one ended by exactly one line break, no line ending in a space, and not starting with
# a space or a line break (which would need an indentation indicator).
_LITERAL = re.compile(r"[\x21-\x7e][\x20-\x7e\n]*(?<![ \n])\n")

_RESOLVER = yaml.resolver.Resolver()


class Unsupported(Exception):
    """A value outside the shapes written here."""


def block_yaml(
    documents: list[Document], literal: type, plain: dict[str, bool] | None = None
) -> str | None:
    """The YAML stream of ``documents`` as ``yaml.dump_all`` writes it, or None when a
    document holds a value outside the shapes written here; ``literal`` is the str
    subclass of the strings to be written as literal blocks. ``plain``: which strings are
    written plain, as found so far by the caller's streams (a bundle's, a run's), else
    this stream's own."""
    writer = _BlockWriter(literal, {} if plain is None else plain)
    try:
        for index, document in enumerate(documents):
            if type(document) is not dict or not document:
                raise Unsupported
            if index:
                writer.out.append("---\n")
            writer.mapping(document, 0, True)
            writer.out.append("\n")
    except Unsupported:
        return None
    return "".join(writer.out)


class _BlockWriter:
    """One stream being written: its text so far, and which strings are plain (asked of
    PyYAML's resolver once per text: manifests repeat their label keys and names many
    times)."""

    def __init__(self, literal: type, plain: dict[str, bool]) -> None:
        self.literal = literal
        self.out: list[str] = []
        self.plain = plain

    def mapping(self, data: dict, indent: int, inline: bool) -> None:
        out = self.out
        for key, value in data.items():
            if not inline:
                out.append("\n" + " " * indent)
            inline = False
            if type(key) is not str or len(key) >= _SIMPLE_KEY:
                raise Unsupported
            out.append(self.scalar(key) + ":")
            kind = type(value)
            if kind is dict and value:
                self.mapping(value, indent + 2, False)
            elif kind is list and value:
                self.sequence(value, indent, False)  # indentless under a key
            elif kind is self.literal:
                if not _LITERAL.fullmatch(value) or " \n" in value:
                    raise Unsupported
                lines = value[:-1].split("\n")
                margin = " " * (indent + 2)
                out.append(" |" + "".join(f"\n{margin}{line}" if line else "\n" for line in lines))
            else:
                out.append(" " + self.value(value))

    def sequence(self, items: list, indent: int, inline: bool) -> None:
        out = self.out
        for item in items:
            if not inline:
                out.append("\n" + " " * indent)
            inline = False
            out.append("- ")
            kind = type(item)
            if kind is dict and item:
                self.mapping(item, indent + 2, True)
            elif kind is list and item:
                self.sequence(item, indent + 2, True)
            elif kind is self.literal:
                raise Unsupported
            else:
                out.append(self.value(item))

    def value(self, value: object) -> str:
        kind = type(value)
        if kind is str:
            return self.scalar(cast(str, value))
        if kind is bool:
            return "true" if value else "false"
        if kind is int:
            return str(value)
        if value is None:
            return "null"
        if kind is dict:  # empty ones: written in flow style
            return "{}"
        if kind is list:
            return "[]"
        raise Unsupported

    def scalar(self, text: str) -> str:
        plain = self.plain.get(text)
        if plain is None:
            if len(text) > _LONGEST or not _SIMPLE.fullmatch(text):
                raise Unsupported
            tag = _RESOLVER.resolve(yaml.ScalarNode, text, (True, False))
            plain = self.plain[text] = tag == _RESOLVER.DEFAULT_SCALAR_TAG
        return text if plain else f"'{text}'"
