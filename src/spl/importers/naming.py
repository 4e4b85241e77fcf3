"""Names and string literals in the words of spl's languages, for model text an
importer writes (docs/import.md): identifiers that are no keyword of the .tsm, .fm or
.rm, unlike the names already taken, and double-quoted literals with the languages'
escapes (docs/tsm.md, "Files")."""

from __future__ import annotations

import re

from spl.dsl.grammar_keywords import keywords

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f]")


def reserved_words() -> frozenset[str]:
    return keywords("tsm") | keywords("fm") | keywords("rm")


def is_name(text: str) -> bool:
    return bool(_IDENTIFIER.match(text)) and text not in reserved_words()


def feature_name(word: str, taken: set[str], fallback: str) -> str:
    """An identifier for ``word``, unlike every name in ``taken``."""
    for candidate in (word, fallback):
        name = re.sub(r"[^A-Za-z0-9_]", "_", candidate)
        name = name if re.match(r"[A-Za-z_]", name) else f"v_{name}"
        if name not in taken and name not in reserved_words():
            return name
    number = 2
    while f"{name}_{number}" in taken:
        number += 1
    return f"{name}_{number}"


def string_literal(text: str) -> str | None:
    """``text`` as a double-quoted literal of the languages (None: it cannot be one)."""
    if _CONTROL.search(text):
        return None
    escaped = text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
    return '"' + escaped.replace("\t", "\\t") + '"'
