"""The transform compiler: generated Python computes what the expression says, turns
arithmetic trouble into per-record errors, and never emits text it did not validate."""

from __future__ import annotations

import ast
import math
from pathlib import Path
from types import ModuleType

import pytest

from spl.core.diagnostics import ModelError
from spl.generators.service.expressions import compile_transform, transforms_module

from support.service_runtime import load_module
from support.transform_trees import T, binary, call, num, ref, transform


def compiled(tmp_path: Path, t, name: str = "probe") -> ModuleType:  # type: ignore[no-untyped-def]
    path = tmp_path / f"{name}.py"
    path.write_text(transforms_module([t]))
    return load_module(path, f"transforms_{name}_{id(t)}")


CURRENT = {"x": 9.0, "n": 7, "ok": True, "label": "a", "timestamp": 100.0}
PREV = {"x": 4.0, "n": 1, "ok": False, "label": "b", "timestamp": 90.0}
NEXT = {"x": 1.0, "n": 2, "ok": True, "label": "c", "timestamp": 130.0}

CASES = [
    (binary("/", ref("x"), num("3600.0")), 9.0 / 3600.0),
    (binary("-", ref("timestamp", "next"), ref("timestamp")), 30.0),
    (binary("-", ref("x"), ref("x", "prev")), 5.0),
    (binary("%", ref("n"), num("4")), 3.0),
    (binary("*", binary("+", ref("n"), num("1")), num("2.5e1")), 200.0),
    (call("sqrt", ref("x")), 3.0),
    (call("atan2", num("1"), num("1")), math.pi / 4),
    (call("max", ref("x"), ref("n"), num("12")), 12.0),
    (
        call("if", binary("and", ref("ok"), binary(">=", ref("x"), num("9"))), num("1"), num("2")),
        1.0,
    ),
    (call("if", T.UnaryExpression(operator="not", operand=ref("ok")), num("1"), num("2")), 2.0),
    (T.UnaryExpression(operator="-", operand=call("floor", num("2.5"))), -2.0),
    (binary("*", ref("pi"), num("2")), 2 * math.pi),
    (call("round", binary("/", ref("n"), num("2"))), 4.0),
]


@pytest.mark.parametrize(("expression", "expected"), CASES)
def test_compiled_expressions_compute_the_model_semantics(tmp_path, expression, expected) -> None:
    module = compiled(tmp_path, transform(value=expression))
    result = module.transform_Probe(dict(CURRENT), dict(PREV), dict(NEXT))
    assert math.isclose(result["value"], expected)
    assert isinstance(result["value"], float)


@pytest.mark.parametrize(
    "expression",
    [
        binary("/", ref("x"), num("0")),
        binary("%", ref("n"), binary("-", ref("n"), ref("n"))),
        call("sqrt", T.UnaryExpression(operator="-", operand=num("1"))),
        call("log", num("0")),
        call("exp", num("1000")),
        call("asin", num("2")),
        binary("-", ref("timestamp", "next"), ref("timestamp")),
    ],
)
def test_arithmetic_trouble_is_a_per_record_error(tmp_path, expression) -> None:
    module = compiled(tmp_path, transform(value=expression))
    with pytest.raises(module.RecordError, match="Probe"):
        module.transform_Probe(dict(CURRENT), None, None)


def test_neighbours_used_and_output_conversion(tmp_path) -> None:
    t = transform(output_type="int", count=binary("+", ref("n"), ref("n", "prev")))
    _, records = compile_transform(t)
    assert records == {"prev"}
    module = compiled(tmp_path, t)
    assert module.transform_Probe(CURRENT, PREV, None) == {"count": 8}


HOSTILE_FIELDS = [
    "x'] or __import__('os').system('id') or current['x",
    "__class__.__bases__",
    "x\n    import os",
    "",
]


@pytest.mark.parametrize("field", HOSTILE_FIELDS)
def test_hostile_field_references_are_refused(field: str) -> None:
    with pytest.raises(ModelError, match="invalid field name"):
        compile_transform(transform(value=ref(field)))


@pytest.mark.parametrize(
    ("expression", "message"),
    [
        (num("1); import os; (1"), "invalid number"),
        (num("1e999"), "out of range"),
        (binary("**", num("2"), num("3")), "unknown operator"),
        (binary("if", num("2"), num("3")), "unknown operator"),
        (call("__import__", num("1")), "unknown function"),
        (call("eval", num("1")), "unknown function"),
        (call("sqrt", num("1"), num("2")), "takes 1 argument"),
        (T.UnaryExpression(operator="~", operand=num("1")), "unknown unary operator"),
        (ref("x", "self"), "unknown record"),
        (ref("nothing"), "no field 'nothing'"),
    ],
)
def test_expressions_outside_the_language_are_refused(expression, message: str) -> None:
    with pytest.raises(ModelError, match=message):
        compile_transform(transform(value=expression))


def test_hostile_names_never_reach_the_code() -> None:
    with pytest.raises(ModelError, match="invalid transform name"):
        compile_transform(transform(name="P(): pass\nimport os\ndef Q", value=num("1")))
    bad_target = transform(value=num("1"))
    bad_target.assignments[0].field = "value': __import__('os'), 'x"
    with pytest.raises(ModelError, match="invalid field name"):
        compile_transform(bad_target)


def test_generated_module_calls_only_known_names() -> None:
    t = transform(
        a=call("sqrt", ref("x")),
        b=binary("/", ref("n"), ref("x", "next")),
        c=call("if", ref("ok"), ref("pi"), num("2")),
    )
    tree = ast.parse(transforms_module([t]))
    called = {ast.unparse(node.func) for node in ast.walk(tree) if isinstance(node, ast.Call)}
    allowed = {
        "math.sqrt",
        "_div",
        "_mod",
        "_neighbour",
        "_double",
        "_int",
        "_bool",
        "_string",
        "float",
        "int",
        "bool",
        "str",
        "RecordError",
        "ZeroDivisionError",
        "ValueError",
        "math.isfinite",
        "isinstance",
    }
    assert called <= allowed, called - allowed
    imports = {
        alias.name
        for node in ast.walk(tree)
        if isinstance(node, ast.Import)
        for alias in node.names
    }
    assert imports == {"math"}


def test_located_errors_point_at_the_expression() -> None:
    bad = ref("missing")
    bad.srcFile, bad.srcLine, bad.srcCol = "data.tsm", 12, 9
    with pytest.raises(ModelError) as caught:
        compile_transform(transform(value=bad))
    assert str(caught.value.diagnostics[0]).startswith("data.tsm:12:9: error:")
