"""Indented JSON text exactly as ``json.dumps(value, indent=2, ...)`` writes it, written
about twice as fast.

The standard library writes indented JSON with its pure-Python encoder (its C encoder
only writes unindented text): one generator per value and level, a third of writing
a product's manifest, Rapyuta and Zenoh files. Bundles are read by people and diffed
between products, so they stay indented and byte for byte the same; this writer covers
the values generators build (dicts with text keys, lists, tuples, text, int, float,
bool, None) and hands anything else to ``json.dumps``, which then writes (or refuses)
it as before. tests/test_json_text.py checks it against json.dumps.
"""

from __future__ import annotations

import json
from json.encoder import encode_basestring_ascii
from typing import Any

_INFINITY = float("inf")

# A JSON (or YAML) document as the generators build it: text keys in the order built,
# values of JSON's kinds (nested documents, lists, text, numbers, booleans, None).
Document = dict[str, object]


class _Unusual(Exception):
    """A value this writer leaves to json.dumps."""


def indented(value: object, sort_keys: bool = False, allow_nan: bool = True) -> str:
    """``json.dumps(value, indent=2, sort_keys=sort_keys, allow_nan=allow_nan)``."""
    chunks: list[str] = []
    try:
        _write(value, "\n", sort_keys, allow_nan, chunks)
    except _Unusual:
        return json.dumps(value, indent=2, sort_keys=sort_keys, allow_nan=allow_nan)
    return "".join(chunks)


def _write(value: Any, margin: str, sort_keys: bool, allow_nan: bool, out: list[str]) -> None:
    """``value`` appended to ``out``; ``margin`` is a line break and the indentation of
    the line the value is on."""
    kind = type(value)
    if kind is str:
        out.append(encode_basestring_ascii(value))
    elif value is None:
        out.append("null")
    elif value is True:
        out.append("true")
    elif value is False:
        out.append("false")
    elif kind is int:
        out.append(int.__repr__(value))
    elif kind is float:
        if value != value or value in (_INFINITY, -_INFINITY):
            if not allow_nan:
                raise _Unusual  # json.dumps raises its own ValueError
            out.append("NaN" if value != value else "Infinity" if value > 0 else "-Infinity")
        else:
            out.append(float.__repr__(value))
    elif len(margin) > 200:
        raise _Unusual  # a hundred levels deep, maybe a cycle: json.dumps reports it
    elif kind is dict:
        if not value:
            out.append("{}")
            return
        inner = margin + "  "
        items = value.items()
        if any(type(key) is not str for key in value):
            raise _Unusual  # json.dumps turns numbers into keys, or refuses
        if sort_keys:
            items = sorted(items)
        separator = "{" + inner
        for key, item in items:
            out.append(separator)
            out.append(encode_basestring_ascii(key))
            out.append(": ")
            _write(item, inner, sort_keys, allow_nan, out)
            separator = "," + inner
        out.append(margin + "}")
    elif kind is list or kind is tuple:
        if not value:
            out.append("[]")
            return
        inner = margin + "  "
        separator = "[" + inner
        for item in value:
            out.append(separator)
            _write(item, inner, sort_keys, allow_nan, out)
            separator = "," + inner
        out.append(margin + "]")
    else:
        raise _Unusual
