"""Transform expressions built with the metamodel's classes, for the transform compiler
and the type checker: one input record type and small constructors for each node."""

from __future__ import annotations

from spl.metamodels import tsm

T = tsm()


def data(name: str, **fields: str):  # type: ignore[no-untyped-def]
    dt = T.DataType(name=name)
    for field, kind in fields.items():
        dt.fields.append(T.Field(name=field, type=T.FieldType.getEEnumLiteral(kind)))
    return dt


IN = data("Sample", x="double", n="int", ok="bool", label="string")


def ref(field: str, record: str = ""):  # type: ignore[no-untyped-def]
    return T.FieldReference(record=record, field=field)


def num(text: str):  # type: ignore[no-untyped-def]
    return T.NumberLiteral(value=text)


def binary(op: str, left, right):  # type: ignore[no-untyped-def]
    return T.BinaryExpression(operator=op, left=left, right=right)


def call(function: str, *args):  # type: ignore[no-untyped-def]
    c = T.CallExpression(function=function)
    c.arguments.extend(args)
    return c


def transform(name: str = "Probe", output_type: str = "double", **assignments):  # type: ignore[no-untyped-def]
    out = data("Out", **{field: output_type for field in assignments})
    t = T.Transform(name=name, input=IN, output=out)
    for field, expression in assignments.items():
        t.assignments.append(T.Assignment(field=field, expression=expression))
    return t
