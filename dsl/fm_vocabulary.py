"""The words and values every feature-model reader shares (.fm, UVL, FeatureIDE XML).

Kept apart from the .fm parser (``spl.dsl.fm``, which loads textX and the pyecore
metamodel) so the UVL reader and ``spl analyze`` can use them without paying for
either import.
"""

from __future__ import annotations

import re

from spl.diagnostics import Diagnostic, Location
from spl.dsl import literals

# Words of the .fm language that can never name a feature (the grammar rejects them
# where a feature name is expected); importers rename features called like this.
RESERVED_WORDS = frozenset(
    {
        "abstract",
        "and",
        "attribute",
        "constraints",
        "excludes",
        "group",
        "mandatory",
        "not",
        "optional",
        "or",
        "requires",
        "sharing",
        "xor",
    }
)
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
ATTRIBUTE_TYPES = ("int", "double", "string", "bool")
SHARING_MODES = ("public", "protected", "private")
# Binary operators of the metamodel, as the .fm language spells them.
OPERATORS = ("and", "or", "implies", "iff", "requires", "excludes")


def is_feature_name(name: str) -> bool:
    """True when ``name`` can be written as a feature name in a .fm file."""
    return bool(IDENTIFIER.match(name)) and name not in RESERVED_WORDS


def too_deep(filename: str) -> Diagnostic:
    """The error for input nested beyond what the readers follow (a hostile file)."""
    return Diagnostic(
        Location(filename, 1, 1), "the model is nested too deeply (features or parentheses)"
    )


def canonical_value(type_name: str, text: str) -> str | None:
    """The canonical text of a default value of ``type_name``, or None when it does not fit.

    Canonical means one spelling per value (``1.0`` and ``1.`` are the same double), so
    comparing models compares values, and every importer agrees with the .fm language.
    """
    if type_name == "bool":
        return text if text in ("true", "false") else None
    if type_name == "int":
        value = literals.int_literal(text)
        return str(value) if value is not None else None
    if type_name == "double":
        try:
            number = float(text)
        except ValueError:
            return None
        if number != number or number in (float("inf"), float("-inf")):
            return None
        return repr(number)
    return text
