"""Print an ``fm.FeatureModel`` as .fm text in one canonical form.

Any model the .fm parser or the UVL / FeatureIDE importers build prints to text that
parses back to the same model (``spl.core.emf_compare.differences`` is empty), so ``spl convert``
can turn community models into .fm files people then edit. The canonical form:

- a feature whose only content is one ``xor``/``or``/``group`` group is written with
  the group after its name (``mandatory MobileBase xor { YouBot Roomba }``);
  otherwise its attributes, sharing mode, capability conditions (one ``capability``
  line each) and groups go in a ``{ }`` body in that order;
- a group written right after a feature name belongs to that feature, so a leaf child
  followed by a group of its parent is closed with an empty body (``optional A { }``);
- a mandatory/optional group is written as ``mandatory A`` lines; a group directly
  following another group of the same kind would merge with it when parsed, so it is
  written as a block ``mandatory { A B }`` instead;
- formulas get the fewest parentheses the precedence (not > and > or > => requires
  excludes > <=>) allows; and/or/<=> associate to the left, implications to the right.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

INDENT = "    "
# (precedence level, how operands of the same level nest without parentheses)
_LEVELS = {"iff": 0, "implies": 1, "requires": 1, "excludes": 1, "or": 2, "and": 3}
_FM_SYMBOLS = {
    "iff": "<=>",
    "implies": "=>",
    "requires": "requires",
    "excludes": "excludes",
    "or": "or",
    "and": "and",
    "not": "not ",
}
_INLINE_WIDTH = 100


def print_model(model: Any) -> str:
    """The canonical .fm text of ``model`` (ends with a newline)."""
    lines = [f"feature model {model.name}", ""]
    root = model.root
    lines.append("root " + _head(root) + _rest(root, ""))
    if model.constraints:
        lines.append("")
        lines.append("constraints {")
        for constraint in model.constraints:
            lines.append(INDENT + format_formula(constraint.formula))
        lines.append("}")
    return "\n".join(lines) + "\n"


def format_formula(
    formula: Any,
    name_of: Callable[[Any], str] = lambda feature: feature.name,
    symbols: dict[str, str] | None = None,
    right_assoc_implication: bool = True,
) -> str:
    """A formula (pyecore, or a plain model's tuple tree) as text with minimal parentheses.

    ``symbols`` and ``name_of`` let the UVL writer reuse this with its own operators and
    quoted names. With ``right_assoc_implication`` false, nested implications and
    equivalences are always parenthesised (for readers whose associativity differs).
    """
    symbols = symbols or _FM_SYMBOLS

    def parts(node: Any) -> tuple[str, Any, Any]:
        """(operator, left, right), ("ref", name, None) or ("not", operand, None)."""
        if isinstance(node, tuple):  # a plain model's tree (spl.dsl.fm.plain): names as is
            return node[0], node[1], (node[2] if node[0] not in ("ref", "not") else None)
        kind = node.eClass.name
        if kind == "FeatureRef":
            return "ref", name_of(node.feature), None
        if kind == "Not":
            return "not", node.operand, None
        return node.operator, node.left, node.right

    def text(node: Any) -> tuple[str, int]:
        operator, left_node, right_node = parts(node)
        if operator == "ref":
            return left_node, 5
        if operator == "not":
            inner, level = text(left_node)
            if level < 4:
                inner = f"({inner})"
            return symbols["not"] + inner, 4
        level = _LEVELS[operator]
        left, left_level = text(left_node)
        right, right_level = text(right_node)
        if level == 1 and right_assoc_implication:
            wrap_left, wrap_right = left_level <= level, right_level < level
        elif level <= 1:
            wrap_left, wrap_right = left_level <= level, right_level <= level
        else:
            wrap_left, wrap_right = left_level < level, right_level <= level
        if wrap_left:
            left = f"({left})"
        if wrap_right:
            right = f"({right})"
        return f"{left} {symbols[operator]} {right}", level

    return text(formula)[0]


def quote_string(value: str) -> str:
    """A .fm string literal for ``value``."""
    escaped = (
        value.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\t", "\\t")
    )
    return f'"{escaped}"'


def _literal(attribute: Any) -> str:
    if attribute.type.name == "string":
        return quote_string(attribute.value or "")
    return attribute.value or ""


def format_capability(condition: Any) -> str:
    """One capability condition as the .fm language writes it: ``base = "youbot"``."""
    if not condition.operator:
        return condition.key
    value = condition.value or ""
    if condition.valueType.name == "string":
        value = f'"{value}"'
    return f"{condition.key} {condition.operator} {value}"


def format_capabilities(feature: Any) -> str:
    """All capability conditions of a feature as one text (``a = "x" and b``): the value
    of the ``capability`` attribute UVL and FeatureIDE files carry."""
    return " and ".join(format_capability(c) for c in feature.capabilities)


def _is_leaf(feature: Any) -> bool:
    return (
        not feature.groups
        and not feature.attributes
        and feature.sharing is None
        and not feature.capabilities
    )


def _head(feature: Any) -> str:
    return ("abstract " if feature.abstract else "") + feature.name


def _has_head_group(feature: Any) -> bool:
    return (
        len(feature.groups) == 1
        and feature.groups[0].kind.name in ("alternative", "or", "cardinality")
        and not feature.attributes
        and feature.sharing is None
        and not feature.capabilities
    )


def _rest(feature: Any, indent: str) -> str:
    """What follows a feature's name: its head group or its body (possibly nothing)."""
    if _is_leaf(feature):
        return ""
    if _has_head_group(feature):
        return " " + _choice_group(feature.groups[0], indent)
    inner = indent + INDENT
    lines = []
    for attribute in feature.attributes:
        lines.append(
            f"{inner}attribute {attribute.name} : {attribute.type.name} = {_literal(attribute)}"
        )
    if feature.sharing is not None:
        lines.append(f"{inner}sharing {feature.sharing.mode.name}")
    for condition in feature.capabilities:
        lines.append(f"{inner}capability {format_capability(condition)}")
    previous_child_kind = None
    groups = list(feature.groups)
    for index, group in enumerate(groups):
        kind = group.kind.name
        if kind in ("mandatory", "optional"):
            if previous_child_kind == kind:
                lines.append(f"{inner}{kind} " + _members(group, inner))
                previous_child_kind = None
                continue
            for child in group.features:
                lines.append(f"{inner}{kind} " + _head(child) + _rest(child, inner))
            following = groups[index + 1] if index + 1 < len(groups) else None
            if (
                following is not None
                and following.kind.name not in ("mandatory", "optional")
                and group.features
                and _is_leaf(group.features[-1])
            ):
                # a group right after a name belongs to that feature: end the leaf first
                lines[-1] += " { }"
            previous_child_kind = kind
        else:
            lines.append(inner + _choice_group(group, inner))
            previous_child_kind = None
    return " {\n" + "\n".join(lines) + "\n" + indent + "}"


def _choice_group(group: Any, indent: str) -> str:
    kind = group.kind.name
    if kind == "alternative":
        keyword = "xor"
    elif kind == "or":
        keyword = "or"
    else:
        upper = "*" if group.upper == -1 else str(group.upper)
        keyword = f"group [{group.lower}..{upper}]"
    return keyword + " " + _members(group, indent)


def _members(group: Any, indent: str) -> str:
    members = list(group.features)
    if all(_is_leaf(m) for m in members):
        inline = "{ " + " ".join(_head(m) for m in members) + " }"
        if len(indent) + len(inline) <= _INLINE_WIDTH:
            return inline
    inner = indent + INDENT
    lines = [inner + _head(m) + _rest(m, inner) for m in members]
    return "{\n" + "\n".join(lines) + "\n" + indent + "}"
