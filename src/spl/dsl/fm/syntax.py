"""Syntax errors of the .fm language and its capability conditions, in a user's words.

textX reports what it expected as grammar rules; the labels here say "feature name",
"number or '*'" instead, for the rules of ``fm.tx`` and ``capability.tx`` alike (the
capability grammar also reads conditions written inside UVL and FeatureIDE files).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from spl.core.diagnostics import Diagnostic, Location
from spl.dsl.grammar_comments import is_comment

if TYPE_CHECKING:
    from textx import TextXSyntaxError


def syntax_diagnostic(exc: TextXSyntaxError, filename: str) -> Diagnostic:
    """A textX syntax error as one located diagnostic naming what was expected."""
    expected = sorted({_rule_label(r) for r in exc.expected_rules or [] if not is_comment(r)})
    if expected:
        listed = (
            ", ".join(expected[:-1]) + " or " + expected[-1] if len(expected) > 1 else expected[0]
        )
        reason = "syntax error: expected " + listed
    else:
        reason = "syntax error: " + str(exc.message).split(" at position")[0]
    return Diagnostic(Location(filename, exc.line or 0, exc.col or 0), reason)


_RULE_LABELS = {
    "FeatureName": "feature name",
    "Ident": "name",
    "Natural": "number",
    "Bound": "number or '*'",
    "QuotedString": "string",
    "BoolWord": "true or false",
    "DoubleNumber": "number",
    "IntNumber": "number",
    "EOF": "end of file",
    "CapabilityKey": "capability name",
    "CapabilityOperator": "operator",
    "CapabilityQuoted": "string",
    "CapabilityBoolWord": "true or false",
    "CapabilityDoubleNumber": "number",
    "CapabilityIntNumber": "number",
}


def _rule_label(rule: Any) -> str:
    name = getattr(rule, "rule_name", "") or ""
    if name in _RULE_LABELS:
        return _RULE_LABELS[name]
    text = str(rule)
    if text.startswith("/(?!(abstract"):
        return "feature name"
    return f"'{text}'"
