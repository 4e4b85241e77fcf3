"""Data types and transforms of the .tsm language, with their expressions.

A transform maps a record of its input data type to one of its output type, one
expression per output field. Expressions are built into the metamodel's Expression
classes and never evaluated here: the names they use (fields, ``prev``/``next``
records, constants) and the functions they call are checked against a closed list, so
the generators can map every one of them to safe code. Their types are checked once
the whole model is built (``transform_types``).
"""

from __future__ import annotations

import math
import re
from typing import Any

from spl.dsl import grammar_keywords, literals
from spl.dsl.tsm.names import Names
from spl.dsl.tsm.syntax import kind

# Functions a transform may call, with (fewest, most) arguments; `if(c, a, b)` is the
# conditional. Nothing else can be called, so generated code can map each one safely
# (the same table as src/spl/generators/service/expressions.py).
FUNCTIONS: dict[str, tuple[int, int]] = {
    "abs": (1, 1),
    "min": (2, 16),
    "max": (2, 16),
    "sqrt": (1, 1),
    "exp": (1, 1),
    "log": (1, 1),
    "sin": (1, 1),
    "cos": (1, 1),
    "tan": (1, 1),
    "asin": (1, 1),
    "acos": (1, 1),
    "atan": (1, 1),
    "atan2": (2, 2),
    "floor": (1, 1),
    "ceil": (1, 1),
    "round": (1, 1),
    "if": (3, 3),
}
CONSTANTS = {"pi": math.pi, "e": math.e}
NEIGHBOURS = ("prev", "next")
IMPLICIT_FIELD = "timestamp"
# Words an expression reads specially; a data field may not be called so: the keywords
# and literals of tsm.tx's expressions (and, or, not, true, false) and the names above.
RESERVED_FIELD_NAMES = frozenset(
    {
        *grammar_keywords.words_of("tsm", "Expression"),
        *grammar_keywords.literal_words("tsm", "Boolean"),
        "if",
        IMPLICIT_FIELD,
        *NEIGHBOURS,
        *CONSTANTS,
    }
)


# -- declarations -----------------------------------------------------------------------
def data_type(names: Names, tree: Any) -> Any:
    """The DataType of a ``data`` block, its fields checked and declared."""
    T = names.T
    data_type = names.locate(T.DataType(name=tree.name.name), tree.name)
    names.declare(names.data_types, data_type, tree.name, "data type")
    fields: dict[str, Any] = {}
    for field_tree in tree.fields:
        name = field_tree.name.name
        field = names.locate(
            T.Field(name=name, type=names.literal("FieldType", field_tree.type)),
            field_tree.name,
        )
        if name in RESERVED_FIELD_NAMES:
            names.error(
                field_tree.name,
                f"field name {name} is reserved in transform expressions"
                + (" (every record has a timestamp)" if name == IMPLICIT_FIELD else ""),
            )
        names.declare(fields, field, field_tree.name, "field", f" in data {data_type.name}")
        data_type.fields.append(field)
    return data_type


def transform(names: Names, tree: Any) -> Any:
    """The Transform of a ``transform`` block; its types and assignments resolve later."""
    transform = names.locate(names.T.Transform(name=tree.name.name), tree.name)
    names.declare(names.transforms, transform, tree.name, "transform")
    names.later(_resolve_transform, transform, tree)
    return transform


def _resolve_transform(names: Names, transform: Any, tree: Any) -> None:
    source = names.data_type(tree.input)
    target = names.data_type(tree.output)
    transform.input, transform.output = source, target
    assigned: dict[str, Any] = {}
    outputs = {f.name for f in target.fields} if target is not None else None
    for assignment_tree in tree.assignments:
        name = assignment_tree.field.name
        assignment = names.locate(names.T.Assignment(field=name), assignment_tree.field)
        if outputs is not None and name not in outputs:
            reason = (
                "the timestamp is kept from the input record"
                if name == IMPLICIT_FIELD
                else f"fields: {', '.join(sorted(outputs)) or 'none'}"
            )
            names.error(
                assignment_tree.field,
                f"unknown field {name} of output type {target.name} ({reason})",
            )
        elif name in assigned:
            names.error(
                assignment_tree.field,
                f"field {name} is assigned twice (first at line {assigned[name].srcLine})",
            )
        else:
            assigned[name] = assignment
        expression = _expression(names, assignment_tree.expression, source)
        if expression is not None:
            assignment.expression = expression
        transform.assignments.append(assignment)
    if outputs is not None:
        missing = [f.name for f in target.fields if f.name not in assigned]
        if missing:
            names.error(
                tree.name,
                f"transform {transform.name} does not assign field(s) "
                f"{', '.join(missing)} of {target.name}",
            )


# -- expressions --------------------------------------------------------------------------
def _expression(names: Names, tree: Any, record_type: Any) -> Any:
    """The Expression model of ``tree``; None (with errors reported) when refused."""
    T = names.T
    rule = kind(tree)
    if rule in ("OrExpr", "AndExpr"):
        operator = "or" if rule == "OrExpr" else "and"
        return _fold(names, tree.operands, [operator] * (len(tree.operands) - 1), record_type)
    if rule in ("Additive", "Multiplicative"):
        return _fold(names, tree.operands, tree.operators, record_type)
    if rule == "NotOp":
        operand = _expression(names, tree.operand, record_type)
        if operand is None:
            return None
        return names.locate(T.UnaryExpression(operator="not", operand=operand), tree)
    if rule == "Negation":
        operand = _expression(names, tree.operand, record_type)
        if operand is None:
            return None
        return names.locate(T.UnaryExpression(operator="-", operand=operand), tree)
    if rule == "Comparison":
        left = _expression(names, tree.left, record_type)
        if tree.operator is None or tree.operator == "":
            return left
        right = _expression(names, tree.right, record_type)
        if left is None or right is None:
            return None
        return names.locate(
            T.BinaryExpression(operator=tree.operator, left=left, right=right), tree
        )
    if rule == "Postfix":
        if tree.indexes:
            names.error(tree.indexes[0], "indexing is not allowed in transform expressions")
            return None
        return _expression(names, tree.primary, record_type)
    if rule == "Parenthesized":
        return _expression(names, tree.inner, record_type)
    if rule == "NumberLiteral":
        return _number(names, tree, tree.value)
    if rule == "BooleanLiteral":
        return names.locate(T.BooleanLiteral(value=tree.value == "true"), tree)
    if rule == "StringLiteral":
        names.error(tree, "strings are not allowed in transform expressions")
        return None
    if rule == "Call":
        return _call(names, tree, record_type)
    if rule == "Reference":
        return _reference(names, tree, record_type)
    raise AssertionError(f"unhandled expression rule {rule}")  # grammar and builder disagree


def _fold(names: Names, operand_trees: list, operators: list, record_type: Any) -> Any:
    """Operands joined by operators, left to right: ``a - b - c`` is ``(a - b) - c``."""
    operands = [_expression(names, o, record_type) for o in operand_trees]
    if any(o is None for o in operands):
        return None
    result = operands[0]
    for operator, operand in zip(operators, operands[1:], strict=True):
        binary = names.T.BinaryExpression(operator=operator, left=result, right=operand)
        result = names.locate(binary, operand_trees[0])
    return result


def _number(names: Names, tree: Any, text: str) -> Any:
    if re.fullmatch(r"\d+", text):
        value = literals.int_literal(text)
        if value is None:
            names.error(tree, f"number {text} is out of range")
            return None
        canonical = str(value)
    else:
        number = float(text)
        if not math.isfinite(number):
            names.error(tree, f"number {text} is out of range")
            return None
        canonical = repr(number)
    return names.locate(names.T.NumberLiteral(value=canonical), tree)


def _call(names: Names, tree: Any, record_type: Any) -> Any:
    name = tree.function.name
    arity = FUNCTIONS.get(name)
    if arity is None:
        names.error(
            tree.function,
            f"unknown function {name} (allowed: {', '.join(sorted(FUNCTIONS))})",
        )
        return None
    fewest, most = arity
    count = len(tree.arguments)
    if not fewest <= count <= most:
        wanted = str(fewest) if fewest == most else f"{fewest} to {most}"
        noun = "argument" if wanted == "1" else "arguments"
        names.error(tree.function, f"function {name} takes {wanted} {noun}, got {count}")
        return None
    arguments = [_expression(names, a, record_type) for a in tree.arguments]
    if any(a is None for a in arguments):
        return None
    call = names.T.CallExpression(function=name)
    call.arguments.extend(arguments)
    return names.locate(call, tree)


def _reference(names: Names, tree: Any, record_type: Any) -> Any:
    parts = tree.parts
    words = [p.name for p in parts]
    known = [f.name for f in record_type.fields] if record_type is not None else []
    known.append(IMPLICIT_FIELD)
    if len(words) == 1 and words[0] in CONSTANTS:
        return names.locate(names.T.NumberLiteral(value=repr(CONSTANTS[words[0]])), tree)
    if len(words) == 2 and words[0] not in NEIGHBOURS and words[0] not in known:
        names.error(parts[0], f"unknown record {words[0]} (write prev.FIELD or next.FIELD)")
        return None
    if len(words) > 2 or (len(words) == 2 and words[0] not in NEIGHBOURS):
        where = parts[2] if words[0] in NEIGHBOURS else parts[1]
        names.error(
            where,
            f"{'.'.join(words)}: attribute chains are not allowed "
            "(write FIELD, prev.FIELD or next.FIELD)",
        )
        return None
    record, field_tree = ("", parts[0]) if len(words) == 1 else (words[0], parts[1])
    field = field_tree.name
    if record_type is not None and field not in known:
        names.error(
            field_tree,
            f"unknown field {field} of {record_type.name} (fields: {', '.join(known)})",
        )
        return None
    return names.locate(names.T.FieldReference(record=record, field=field), tree)
