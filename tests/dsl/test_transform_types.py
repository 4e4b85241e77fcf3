"""Static typing of transforms and stores: every problem reported, located."""

from __future__ import annotations

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.tsm.transform_types import check_system, check_transform, expression_type

from support.service_models import data_acquisition_system
from support.transform_trees import IN, T, binary, call, data, num, ref, transform

TYPED = [
    (num("3"), "int"),
    (num("3.0"), "double"),
    (ref("timestamp", "prev"), "double"),
    (binary("+", ref("n"), num("1")), "int"),
    (binary("/", ref("n"), num("2")), "double"),
    (binary("+", ref("label"), ref("label", "next")), "string"),
    (binary("<", ref("label"), ref("label")), "bool"),
    (binary("==", ref("n"), ref("x")), "bool"),
    (call("floor", ref("x")), "int"),
    (call("min", ref("n"), num("2")), "int"),
    (call("max", ref("n"), ref("x")), "double"),
    (call("if", ref("ok"), ref("n"), ref("x")), "double"),
    (call("pi"), "double"),
    (T.UnaryExpression(operator="not", operand=ref("ok")), "bool"),
]


@pytest.mark.parametrize(("expression", "expected"), TYPED)
def test_expression_types(expression, expected: str) -> None:
    kind, problems = expression_type(expression, transform(value=num("1")))
    assert (kind, problems) == (expected, [])


ILL_TYPED = [
    (binary("+", ref("ok"), num("1")), "operator '+' cannot combine bool and int"),
    (binary("and", ref("n"), ref("ok")), "operator 'and' cannot combine int and bool"),
    (binary("<", ref("label"), num("1")), "cannot combine string and int"),
    (binary("==", ref("label"), ref("ok")), "cannot combine string and bool"),
    (T.UnaryExpression(operator="-", operand=ref("label")), "unary '-' needs a number"),
    (T.UnaryExpression(operator="not", operand=ref("x")), "'not' needs a bool"),
    (call("sqrt", ref("label")), "sqrt() needs numbers, got string"),
    (call("if", ref("x"), num("1"), num("2")), "condition of if() must be bool"),
    (call("if", ref("ok"), num("1"), ref("label")), "different types int, string"),
    (call("atan2", num("1")), "atan2() takes 2 arguments, got 1"),
    (call("min", num("1")), "min() takes at least 2 arguments"),
    (call("system", num("1")), "unknown function 'system'"),
    (ref("missing"), "Sample has no field 'missing'"),
    (ref("x", "other"), "unknown record 'other'"),
]


@pytest.mark.parametrize(("expression", "message"), ILL_TYPED)
def test_ill_typed_expressions_are_reported(expression, message: str) -> None:
    kind, problems = expression_type(expression, transform(value=num("1")))
    assert kind is None
    assert [message in p.message for p in problems] == [True], problems


def test_assignments_must_fit_and_cover_the_refined_type() -> None:
    out = data("Refined", whole="int", real="double", flag="bool", text="string")
    t = T.Transform(name="Refine", input=IN, output=out)
    located = T.Assignment(field="whole", expression=ref("x"))
    located.srcFile, located.srcLine, located.srcCol = "data.tsm", 20, 5
    t.assignments.extend(
        [
            located,  # double -> int: refused
            T.Assignment(field="real", expression=ref("n")),  # int -> double: widened
            T.Assignment(field="real", expression=ref("x")),  # twice
            T.Assignment(field="nothing", expression=num("1")),
        ]
    )
    t.srcFile, t.srcLine, t.srcCol = "data.tsm", 18, 1
    problems = [str(p) for p in check_transform(t)]
    assert problems == [
        "data.tsm:20:5: error: transform Refine: cannot assign double to Refined.whole of type int",
        "data.tsm:18:1: error: transform Refine: field 'real' is assigned twice",
        "data.tsm:18:1: error: transform Refine: Refined has no field 'nothing'",
        "data.tsm:18:1: error: transform Refine: does not assign flag, text of Refined; every "
        "field of a refined type needs a value",
    ]


def test_the_shipped_product_line_is_well_typed() -> None:
    assert check_system(data_acquisition_system()) == []


def test_store_refinements_must_match_their_transform() -> None:
    system = data_acquisition_system()
    stores = {s.name: s for c in system.containers for s in c.stores}
    follow, positions = stores["FollowStore"], stores["PositionStore"]
    follow.refinements[0].transform = positions.refinements[0].transform
    system.dataTypes[0].fields.append(T.Field(name="robot", type=T.FieldType.double))
    messages = [p.message for p in check_system(system)]
    assert any("field name 'robot' is reserved" in m for m in messages)
    assert any(
        "reads PositionInSecond, but the store's raw type is Velocity" in m for m in messages
    )
    assert any("produces PositionInDEG, not Command" in m for m in messages)


def test_typing_problems_are_reported_by_the_tsm_checks_located() -> None:
    from spl.dsl.tsm import language as tsm_language

    with pytest.raises(ModelError) as raised:
        tsm_language.parse_text(
            "system S\n"
            "data A { x : double  n : int  ok : bool }\n"
            "data B { y : int  z : double }\n"
            "transform F : A -> B {\n"
            "    y = x / 2\n"
            "    z = ok + 1\n"
            "}\n"
            "cloud container C {\n"
            "    store St {\n"
            "        raw A\n"
            "        refined B by F every 1 s\n"
            "    }\n"
            "}\n",
            "bad.tsm",
        )
    assert [str(d) for d in raised.value.diagnostics] == [
        "bad.tsm:5:5: error: transform F: cannot assign double to B.y of type int",
        "bad.tsm:6:9: error: transform F: operator '+' cannot combine bool and int",
    ]
