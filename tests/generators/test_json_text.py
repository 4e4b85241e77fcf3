"""json_text.indented writes exactly what json.dumps(indent=2) writes, and raises what
it raises, for every value a generator could hand it and for values it leaves to
json.dumps."""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import given, settings, strategies as st

from spl.generators.json_text import indented

from support.hypothesis_budget import examples

SCALARS = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(),
)
VALUES = st.recursive(
    SCALARS,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4),
        st.lists(inner, max_size=3).map(tuple),
        st.dictionaries(st.text(max_size=5), inner, max_size=4),
    ),
    max_leaves=20,
)


def outcome(write, value, **options):
    try:
        return write(value, **options)
    except (ValueError, TypeError) as error:
        return type(error), str(error)


def dumps(value, **options):
    return json.dumps(value, indent=2, **options)


@settings(max_examples=examples(300), deadline=None)
@given(VALUES, st.booleans(), st.booleans())
def test_any_value_is_written_as_json_dumps_writes_it(value, sort_keys, allow_nan):
    options = {"sort_keys": sort_keys, "allow_nan": allow_nan}
    assert outcome(indented, value, **options) == outcome(dumps, value, **options)


@pytest.mark.parametrize(
    "value",
    [
        {},
        [],
        (),
        {"b": [1, 2.5, {"x": None}], "a": 'é\n"\\', "c": True, "d": (1, "x"), "e": {}},
        [math.nan, math.inf, -math.inf, 1e300, -0.0, 10**30, False],
        {1: "number key", "a": 1},  # json.dumps turns the key into text
        {"a": {1, 2}},  # json.dumps refuses a set
        {"a": object()},
        {None: 1, True: 2},
    ],
)
@pytest.mark.parametrize("sort_keys", [True, False])
def test_values_left_to_json_dumps_and_edge_cases(value, sort_keys):
    for allow_nan in (True, False):
        options = {"sort_keys": sort_keys, "allow_nan": allow_nan}
        assert outcome(indented, value, **options) == outcome(dumps, value, **options)


def test_a_cycle_is_refused_as_json_dumps_refuses_it():
    cycle: list = []
    cycle.append(cycle)
    with pytest.raises(ValueError, match="Circular reference"):
        indented(cycle)
