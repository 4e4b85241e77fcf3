"""Compile transform expressions (tsm ``Expression`` trees) to Python source text.

Transforms come from model text, and model text is hostile: nothing of it is ever
``eval``-ed or pasted into code. The compiler walks the tree and emits only tokens
it owns (operators and functions from fixed tables, literals re-printed from parsed
numbers); field names never become Python identifiers, they become dict keys through
``repr``. Anything the tables do not know is a located ModelError, even if the
parser already refused it, so the compiler is safe on its own.

The generated module is pure: each transform is ``transform_<Name>(current, prev,
next_) -> dict`` over plain dicts, and arithmetic trouble (division by zero, math
domain errors, overflow, non-finite results, a missing neighbour record) raises
``RecordError`` for that one record instead of stopping the transformer.
"""

from __future__ import annotations

import keyword
import math
import re
from collections.abc import Iterable
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Diagnostic, ModelError, location_of
from spl.resolver.architecture.generated_names import IDENTIFIER

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

NUMBER = re.compile(r"(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")

# model operator -> Python operator; '/' and '%' go through helpers (zero checks)
BINARY_OPERATORS = {
    "+": "+",
    "-": "-",
    "*": "*",
    "<": "<",
    "<=": "<=",
    ">": ">",
    ">=": ">=",
    "==": "==",
    "!=": "!=",
    "and": "and",
    "or": "or",
}
HELPER_OPERATORS = {"/": "_div", "%": "_mod"}
UNARY_OPERATORS = {"-": "-", "not": "not "}
# model function -> (Python callable in the generated module, min args, max args)
FUNCTIONS: dict[str, tuple[str, int, int]] = {
    "abs": ("abs", 1, 1),
    "min": ("min", 2, 16),
    "max": ("max", 2, 16),
    "sqrt": ("math.sqrt", 1, 1),
    "exp": ("math.exp", 1, 1),
    "log": ("math.log", 1, 1),
    "sin": ("math.sin", 1, 1),
    "cos": ("math.cos", 1, 1),
    "tan": ("math.tan", 1, 1),
    "asin": ("math.asin", 1, 1),
    "acos": ("math.acos", 1, 1),
    "atan": ("math.atan", 1, 1),
    "atan2": ("math.atan2", 2, 2),
    "floor": ("math.floor", 1, 1),
    "ceil": ("math.ceil", 1, 1),
    "round": ("round", 1, 1),
    "if": ("", 3, 3),  # compiled lazily as a conditional expression
}
CONSTANTS = {"pi": "math.pi", "e": "math.e"}
RECORDS = {
    "": "current",
    "prev": "_neighbour(prev, 'previous')",
    "next": "_neighbour(next_, 'next')",
}
IMPLICIT_FIELDS = ("timestamp",)

# Fixed text of the generated module: helpers the compiled functions call.
RUNTIME = '''\
import math


class RecordError(Exception):
    """One record could not be transformed; the transformer logs it and moves on."""


def _div(a, b):
    if b == 0:
        raise ZeroDivisionError("division by zero")
    return a / b


def _mod(a, b):
    if b == 0:
        raise ZeroDivisionError("modulo by zero")
    return a % b


def _neighbour(record, which):
    if record is None:
        raise RecordError(f"no {which} record of the same robot")
    return record


def _double(value):
    value = float(value)
    if not math.isfinite(value):
        raise ValueError("result is not a finite number")
    return value


def _int(value):
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError("result is not a finite number")
        value = int(value)
    value = int(value)
    if not -(2**63) <= value < 2**63:  # the refined column is 64-bit (SQLite, PostgreSQL)
        raise ValueError("result is outside the 64-bit integer range")
    return value


def _bool(value):
    return bool(value)


def _string(value):
    value = str(value)
    if "\\x00" in value:  # PostgreSQL text cannot hold it
        raise ValueError("result contains a NUL character")
    return value
'''

CONVERTERS = {"double": "_double", "int": "_int", "bool": "_bool", "string": "_string"}


class ExpressionCompiler:
    """Compiles the expressions of one transform; collects every problem it finds."""

    def __init__(self, transform_name: str, input_fields: Iterable[str]) -> None:
        self.transform_name = transform_name
        self.input_fields = set(input_fields)
        self.diagnostics: list[Diagnostic] = []
        self.records_used: set[str] = set()

    def _error(self, element: tsm_types.Located | None, message: str) -> str:
        self.diagnostics.append(
            Diagnostic(location_of(element), f"transform {self.transform_name}: {message}")
        )
        return "None"

    def compile(self, expr: tsm_types.Expression | None) -> str:
        kind = expr.eClass.name if expr is not None else None
        if kind == "BinaryExpression":
            return self._binary(cast("tsm_types.BinaryExpression", expr))
        if kind == "UnaryExpression":
            unary = cast("tsm_types.UnaryExpression", expr)
            operator = UNARY_OPERATORS.get(unary.operator)
            if operator is None:
                return self._error(unary, f"unknown unary operator {unary.operator!r}")
            return f"({operator}{self.compile(unary.operand)})"
        if kind == "CallExpression":
            return self._call(cast("tsm_types.CallExpression", expr))
        if kind == "FieldReference":
            return self._field(cast("tsm_types.FieldReference", expr))
        if kind == "NumberLiteral":
            number = cast("tsm_types.NumberLiteral", expr)
            return self._number(number, number.value)
        if kind == "BooleanLiteral":
            return "True" if cast("tsm_types.BooleanLiteral", expr).value is True else "False"
        return self._error(expr, f"unsupported expression {kind!r}")

    def _binary(self, expr: tsm_types.BinaryExpression) -> str:
        left = self.compile(expr.left)
        right = self.compile(expr.right)
        if expr.operator in HELPER_OPERATORS:
            return f"{HELPER_OPERATORS[expr.operator]}({left}, {right})"
        operator = BINARY_OPERATORS.get(expr.operator)
        if operator is None:
            return self._error(expr, f"unknown operator {expr.operator!r}")
        return f"({left} {operator} {right})"

    def _call(self, expr: tsm_types.CallExpression) -> str:
        name = expr.function
        arguments = list(expr.arguments)
        if name in CONSTANTS and not arguments:
            return CONSTANTS[name]
        entry = FUNCTIONS.get(name)
        if entry is None:
            return self._error(expr, f"unknown function {name!r}")
        target, low, high = entry
        if not low <= len(arguments) <= high:
            wanted = str(low) if low == high else f"{low} to {high}"
            noun = "argument" if wanted == "1" else "arguments"
            return self._error(expr, f"{name}() takes {wanted} {noun}, got {len(arguments)}")
        compiled = [self.compile(a) for a in arguments]
        if name == "if":
            condition, then, otherwise = compiled
            return f"({then} if {condition} else {otherwise})"
        return f"{target}({', '.join(compiled)})"

    def _field(self, expr: tsm_types.FieldReference) -> str:
        record = expr.record or ""
        field = expr.field
        if record not in RECORDS:
            return self._error(expr, f"unknown record {record!r} (use prev or next)")
        if not isinstance(field, str) or not IDENTIFIER.match(field):
            return self._error(expr, f"invalid field name {field!r}")
        if field not in self.input_fields and field not in IMPLICIT_FIELDS:
            if record == "" and field in CONSTANTS:
                return CONSTANTS[field]
            return self._error(expr, f"the input record has no field {field!r}")
        self.records_used.add(record)
        return f"{RECORDS[record]}[{field!r}]"

    def _number(self, expr: tsm_types.NumberLiteral, text: object) -> str:
        if isinstance(text, str) and text in CONSTANTS:
            return CONSTANTS[text]
        if not isinstance(text, str) or not NUMBER.match(text):
            return self._error(expr, f"invalid number {text!r}")
        if re.fullmatch(r"[0-9]+", text):
            return repr(int(text))
        value = float(text)
        if not math.isfinite(value):
            return self._error(expr, f"number {text!r} is out of range")
        return repr(value)


def function_name(transform_name: str) -> str:
    return f"transform_{transform_name}"


def compile_transform(transform: tsm_types.Transform) -> tuple[str, set[str]]:
    """Python source of ``transform_<Name>`` and the neighbour records it reads.

    Raises ModelError (all problems, located) when any part is not in the language.
    """
    name = transform.name
    problems: list[Diagnostic] = []
    if not isinstance(name, str) or not IDENTIFIER.match(name) or keyword.iskeyword(name):
        raise ModelError([Diagnostic(location_of(transform), f"invalid transform name {name!r}")])
    input_fields = [f.name for f in transform.input.fields] if transform.input else []
    output = transform.output
    output_types = {f.name: f.type.name for f in output.fields} if output else {}
    compiler = ExpressionCompiler(name, input_fields)
    lines = [
        f"def {function_name(name)}(current, prev, next_):",
        f'    """{name}: {transform.input.name} -> {transform.output.name} (generated)."""',
        "    try:",
        "        return {",
    ]
    for assignment in transform.assignments:
        field = assignment.field
        if not isinstance(field, str) or not IDENTIFIER.match(field):
            problems.append(Diagnostic(location_of(assignment), f"invalid field name {field!r}"))
            continue
        if field not in output_types:
            problems.append(
                Diagnostic(
                    location_of(assignment),
                    f"transform {name}: {transform.output.name} has no field {field!r}",
                )
            )
            continue
        code = compiler.compile(assignment.expression)
        lines.append(f"            {field!r}: {CONVERTERS[output_types[field]]}({code}),")
    lines += [
        "        }",
        "    except (ArithmeticError, ValueError, TypeError, RecordError) as exc:",
        f"        raise RecordError({name + ': '!r} + str(exc)) from exc",
        "",
    ]
    problems += compiler.diagnostics
    if problems:
        raise ModelError(problems)
    records = {r for r in compiler.records_used if r}
    return "\n".join(lines), records


def transforms_module(transforms: Iterable[tsm_types.Transform]) -> str:
    """A complete Python module: the runtime helpers plus one function per transform."""
    parts = ['"""Transforms compiled from the template system model by spl. Do not edit."""\n']
    parts.append(RUNTIME)
    problems: list[Diagnostic] = []
    for transform in sorted(transforms, key=lambda t: t.name):
        try:
            source, _ = compile_transform(transform)
        except ModelError as error:
            problems += error.diagnostics
            continue
        parts.append("\n" + source)
    if problems:
        raise ModelError(problems)
    return "\n".join(parts)


def neighbours_used(transform: tsm_types.Transform) -> set[str]:
    """``{'prev', 'next'}`` subset: which neighbouring records the transform reads."""
    return compile_transform(transform)[1]
