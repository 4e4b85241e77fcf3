"""Static typing of data-acquisition transforms (the expression language of ``.tsm``).

A transform runs unattended in a cloud service, long after the model was written; a
type error found there costs a silently skipped record per second. So every
expression gets a type here (int, double, bool, string), operators and functions are
checked against their argument types, each assignment must fit its output field
(an int may widen to double, nothing else converts), and every field of the refined
type must be assigned. Stores are checked too: a refinement's transform must read the
store's raw type and produce the refinement's output type.
"""

from __future__ import annotations

from typing import Any, cast

from spl.core.diagnostics import Diagnostic, location_of

NUMERIC = ("int", "double")
ARITHMETIC = ("+", "-", "*", "/", "%")
ORDERING = ("<", "<=", ">", ">=")
EQUALITY = ("==", "!=")
LOGICAL = ("and", "or")
DOUBLE_FUNCTIONS = ("sqrt", "exp", "log", "sin", "cos", "tan", "asin", "acos", "atan")
ROUNDING_FUNCTIONS = ("floor", "ceil", "round")
CONSTANTS = ("pi", "e")
RECORDS = ("", "prev", "next")
# Columns every refined table and record envelope has; data fields may not reuse them.
RESERVED_FIELDS = ("id", "raw_id", "robot", "timestamp")


def _join(a: str, b: str) -> str | None:
    """The common type of two branches (if/min/max), or None when there is none."""
    if a == b:
        return a
    if a in NUMERIC and b in NUMERIC:
        return "double"
    return None


def assignable(value: str, target: str) -> bool:
    return value == target or (value == "int" and target == "double")


class TransformTyping:
    """Types the expressions of one transform against its input data type."""

    def __init__(self, transform: Any) -> None:
        self.transform = transform
        input_type = transform.input
        self.fields = {f.name: f.type.name for f in input_type.fields} if input_type else {}
        self.diagnostics: list[Diagnostic] = []

    def error(self, element: Any, message: str) -> None:
        self.diagnostics.append(
            Diagnostic(
                location_of(element) or location_of(self.transform),
                f"transform {self.transform.name}: {message}",
            )
        )

    def type_of(self, expr: Any) -> str | None:
        """The expression's type; None (after reporting why) when it has none."""
        kind = expr.eClass.name
        method = getattr(self, f"_{kind}", None)
        if method is None:
            self.error(expr, f"unsupported expression {kind}")
            return None
        return method(expr)

    def _NumberLiteral(self, expr: Any) -> str | None:
        text = expr.value or ""
        if text in CONSTANTS:
            return "double"
        return "int" if text.isdigit() else "double"

    def _BooleanLiteral(self, expr: Any) -> str:
        return "bool"

    def _FieldReference(self, expr: Any) -> str | None:
        record = expr.record or ""
        if record not in RECORDS:
            self.error(expr, f"unknown record {record!r}; use prev or next")
            return None
        if expr.field == "timestamp":
            return "double"
        if expr.field in self.fields:
            return self.fields[expr.field]
        if record == "" and expr.field in CONSTANTS:
            return "double"
        self.error(expr, f"{self.transform.input.name} has no field {expr.field!r}")
        return None

    def _UnaryExpression(self, expr: Any) -> str | None:
        operand = self.type_of(expr.operand)
        if operand is None:
            return None
        if expr.operator == "-":
            if operand in NUMERIC:
                return operand
            self.error(expr, f"unary '-' needs a number, not {operand}")
            return None
        if expr.operator == "not":
            if operand == "bool":
                return "bool"
            self.error(expr, f"'not' needs a bool, not {operand}")
            return None
        self.error(expr, f"unknown unary operator {expr.operator!r}")
        return None

    def _BinaryExpression(self, expr: Any) -> str | None:
        left = self.type_of(expr.left)
        right = self.type_of(expr.right)
        if left is None or right is None:
            return None
        op = expr.operator
        if op in ARITHMETIC:
            if op == "+" and left == right == "string":
                return "string"
            if left in NUMERIC and right in NUMERIC:
                if op == "/":
                    return "double"
                return "int" if left == right == "int" else "double"
        elif op in ORDERING:
            if (left in NUMERIC and right in NUMERIC) or left == right == "string":
                return "bool"
        elif op in EQUALITY:
            if _join(left, right) is not None:
                return "bool"
        elif op in LOGICAL:
            if left == right == "bool":
                return "bool"
        else:
            self.error(expr, f"unknown operator {op!r}")
            return None
        self.error(expr, f"operator {op!r} cannot combine {left} and {right}")
        return None

    def _CallExpression(self, expr: Any) -> str | None:
        name = expr.function
        args = [self.type_of(a) for a in expr.arguments]
        if name in CONSTANTS and not args:
            return "double"
        arity = {"if": 3, "atan2": 2}.get(name, 1)
        if name in ("min", "max"):
            if len(args) < 2:
                self.error(expr, f"{name}() takes at least 2 arguments, got {len(args)}")
                return None
        elif (
            name in DOUBLE_FUNCTIONS or name in ROUNDING_FUNCTIONS or name in ("abs", "atan2", "if")
        ):
            if len(args) != arity:
                noun = "argument" if arity == 1 else "arguments"
                self.error(expr, f"{name}() takes {arity} {noun}, got {len(args)}")
                return None
        else:
            self.error(expr, f"unknown function {name!r}")
            return None
        if any(a is None for a in args):
            return None
        typed = cast("list[str]", args)  # every argument typed
        if name == "if":
            condition, then, otherwise = typed
            if condition != "bool":
                self.error(expr, f"the condition of if() must be bool, not {condition}")
                return None
            joined = _join(then, otherwise)
            if joined is None:
                self.error(expr, f"the branches of if() have different types {then}, {otherwise}")
            return joined
        if not all(a in NUMERIC for a in args):
            self.error(expr, f"{name}() needs numbers, got {', '.join(typed)}")
            return None
        if name in ROUNDING_FUNCTIONS:
            return "int"
        if name in ("abs", "min", "max"):
            return "int" if all(a == "int" for a in args) else "double"
        return "double"


def expression_type(expr: Any, transform: Any) -> tuple[str | None, list[Diagnostic]]:
    """Type of one expression read in the context of ``transform`` (its input type)."""
    typing = TransformTyping(transform)
    return typing.type_of(expr), typing.diagnostics


def check_transform(transform: Any) -> list[Diagnostic]:
    """Every typing problem of one transform, located at the offending element."""
    typing = TransformTyping(transform)
    output = transform.output
    targets = {f.name: f.type.name for f in output.fields} if output else {}
    assigned: set[str] = set()
    for assignment in transform.assignments:
        field = assignment.field
        value = typing.type_of(assignment.expression)
        if field not in targets:
            typing.error(assignment, f"{output.name} has no field {field!r}")
            continue
        if field in assigned:
            typing.error(assignment, f"field {field!r} is assigned twice")
        assigned.add(field)
        if value is not None and not assignable(value, targets[field]):
            typing.error(
                assignment,
                f"cannot assign {value} to {output.name}.{field} of type {targets[field]}",
            )
    missing = [name for name in targets if name not in assigned]
    if missing:
        typing.error(
            transform,
            f"does not assign {', '.join(missing)} of {output.name}; every field of a "
            "refined type needs a value",
        )
    return typing.diagnostics


# A field is a database column: SQLite compares column names without case, PostgreSQL
# keeps the first 63 bytes of an identifier (names are ASCII).
POSTGRES_IDENTIFIER = 63


def check_data_type(data_type: Any) -> list[Diagnostic]:
    problems = []
    columns: dict[str, Any] = {}  # a field's column name as the databases compare it
    for field in data_type.fields:
        where = location_of(field) or location_of(data_type)
        if field.name.lower() in RESERVED_FIELDS:
            problems.append(
                Diagnostic(
                    where,
                    f"data {data_type.name}: field name {field.name!r} is reserved "
                    f"({', '.join(RESERVED_FIELDS)} are columns of every stored record, "
                    "in any case)",
                )
            )
            continue
        first = columns.setdefault(field.name.lower()[:POSTGRES_IDENTIFIER], field)
        if first is not field and first.name != field.name:  # same names: a parse error
            problems.append(
                Diagnostic(
                    where,
                    f"data {data_type.name}: fields {first.name} and {field.name} would be one "
                    "database column (SQLite compares column names without case, PostgreSQL "
                    f"keeps their first {POSTGRES_IDENTIFIER} characters)",
                )
            )
    return problems


def check_system(system: Any) -> list[Diagnostic]:
    """Typing of all transforms, reserved field names, and store/refinement consistency."""
    problems: list[Diagnostic] = []
    for data_type in system.dataTypes:
        problems += check_data_type(data_type)
    for transform in system.transforms:
        problems += check_transform(transform)
    for container in system.containers:
        for store in container.stores:
            outputs: set[str] = set()
            for refinement in store.refinements:
                where = location_of(refinement) or location_of(store)
                transform = refinement.transform
                if transform is None or refinement.output is None or store.raw is None:
                    continue
                if transform.input is not store.raw:
                    problems.append(
                        Diagnostic(
                            where,
                            f"store {store.name}: transform {transform.name} reads "
                            f"{transform.input.name}, but the store's raw type is "
                            f"{store.raw.name}",
                        )
                    )
                if transform.output is not refinement.output:
                    problems.append(
                        Diagnostic(
                            where,
                            (
                                f"store {store.name}: transform {transform.name} produces "
                                f"{transform.output.name}, not {refinement.output.name}"
                            ),
                        )
                    )
                if refinement.output.name in outputs:
                    problems.append(
                        Diagnostic(
                            where,
                            (f"store {store.name}: {refinement.output.name} is refined twice"),
                        )
                    )
                outputs.add(refinement.output.name)
                if refinement.period is not None and not refinement.period > 0:
                    problems.append(
                        Diagnostic(
                            where,
                            (
                                f"store {store.name}: the period of {refinement.output.name} "
                                "must be positive"
                            ),
                        )
                    )
    return problems
