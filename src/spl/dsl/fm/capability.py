"""Capability conditions of features: what a robot must offer to run a feature.

Written ``capability KEY [OP VALUE]`` in a .fm file (``base = "youbot"``,
``memory >= 4``, ``onboard_pc``), and as the text of a string attribute in UVL and
FeatureIDE files; the small grammar ``capability.tx`` reads that text (``fm_reader``
does, or textX for what it leaves), so the three formats build the same
``fm.CapabilityCondition`` and report the same problems.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from spl.core.diagnostics import Diagnostic, DiagnosticSink, Location, ModelError
from spl.dsl.fm import reader as fm_reader
from spl.dsl.fm.syntax import syntax_diagnostic
from spl.dsl.fm.vocabulary import canonical_value
from spl.metamodels import fm as fm_metamodel

if TYPE_CHECKING:
    from spl.metamodels import fm_types


@cache
def _capability_grammar() -> Any:
    from textx import metamodel_from_file  # only what the fast reader leaves needs textX

    return metamodel_from_file(
        str(Path(__file__).with_name("capability.tx")), autokwd=True, use_regexp_group=False
    )


def parse_capability_conditions(text: str, where: Location | None) -> list[Any]:
    """The ``capability`` conditions written as text (``base = "youbot" and onboard_pc``),
    as UVL and FeatureIDE files carry them in a string attribute; problems are reported
    at ``where``, the attribute."""
    tree = fm_reader.read_capabilities(text)
    if tree is None:
        tree = _textx_conditions(text, where)
    sink = DiagnosticSink()
    conditions = [capability_condition(node, where, sink) for node in tree.conditions]
    sink.raise_if_errors()
    return conditions


def _textx_conditions(text: str, where: Location | None) -> Any:
    """textX's tree of capability conditions; a syntax error as a ModelError at ``where``."""
    from textx import TextXSyntaxError

    try:
        return _capability_grammar().model_from_str(text)
    except TextXSyntaxError as exc:
        reason = syntax_diagnostic(exc, "capability").message
        raise ModelError(
            [Diagnostic(where, f"capability {text!r}: {reason} at column {exc.col}")]
        ) from None


_CAPABILITY_LITERALS = {
    "CapabilityString": "string",
    "CapabilityBool": "bool",
    "CapabilityDouble": "double",
    "CapabilityInt": "int",
}


def capability_condition(node: Any, where: Location | None, sink: DiagnosticSink) -> Any:
    """One parsed ``KEY [OP VALUE]`` as an ``fm.CapabilityCondition``; a bound (``>=``,
    ``<=``) on something that is not a number is reported to ``sink``."""
    F = fm_metamodel()
    condition = F.CapabilityCondition(key=node.key, operator=node.operator or "")
    if where is not None:
        condition.srcFile, condition.srcLine, condition.srcCol = where.file, where.line, where.col
    if node.value is not None:
        kind = _CAPABILITY_LITERALS[type(node.value).__name__]
        text = node.value.text[1:-1] if kind == "string" else node.value.text
        condition.valueType = cast("fm_types.AttributeType", F.AttributeType.getEEnumLiteral(kind))
        value = canonical_value(kind, text)
        condition.value = cast(str, value)  # None: not a value of the kind, reported here
        if value is None:
            sink.error(where, f"capability {node.key}: {node.value.text} is not a {kind}")
        elif node.operator in (">=", "<=") and kind not in ("int", "double"):
            sink.error(
                where,
                f"capability {node.key} {node.operator} needs a number, got {node.value.text}",
            )
    return condition
