"""Comparing a fast reader's parse tree with textX's (tests of tsm_reader, fm_reader,
rm_reader).

Where a reader takes a text, its tree must equal textX's object for object: class name,
every attribute of the rule, ``_tx_position``; where textX refuses a text, the reader
must refuse it too (textX then words the syntax error).
"""

from __future__ import annotations

import random
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

from arpeggio import RegExMatch
from textx import TextXSyntaxError

ROOT = Path(__file__).resolve().parents[2]


def shipped(suffix: str) -> list[Path]:
    """Every model file with ``suffix`` in the product lines and the tests."""
    return sorted(
        p for base in ("product_lines", "tests") for p in (ROOT / base).rglob(f"*{suffix}")
    )


def textx_tree(grammar: Any, text: str) -> Any:
    """textX's tree of ``text``, or the name of its refusal."""
    try:
        return grammar.model_from_str(text)
    except TextXSyntaxError:
        return "syntax error"
    except RecursionError:
        return "too deep"


def difference(expected: Any, found: Any, path: str = "tree") -> str | None:
    """Where the reader's tree ``found`` differs from textX's ``expected`` (None: nowhere)."""
    if expected is None or isinstance(expected, str | bool):
        if type(found) is not type(expected) or found != expected:
            return f"{path}: textX {expected!r}, reader {found!r}"
        return None
    if isinstance(expected, list):
        if not isinstance(found, list) or len(found) != len(expected):
            return f"{path}: textX {len(expected)} items, reader {found!r}"
        for index, (a, b) in enumerate(zip(expected, found, strict=True)):
            if (where := difference(a, b, f"{path}[{index}]")) is not None:
                return where
        return None
    rule = type(expected)
    if type(found).__name__ != rule.__name__:
        return f"{path}: textX {rule.__name__}, reader {type(found).__name__}"
    if found._tx_position != expected._tx_position:
        return f"{path}: textX at {expected._tx_position}, reader at {found._tx_position}"
    if set(found._fields) - {"position"} != set(rule._tx_attrs):
        return f"{path}: textX attributes {sorted(rule._tx_attrs)}, reader {found._fields}"
    for attribute in rule._tx_attrs:
        value = getattr(found, attribute)
        if (
            where := difference(getattr(expected, attribute), value, f"{path}.{attribute}")
        ) is not None:
            return where
    return None


def assert_reads_as_textx(
    read: Callable[[str], Any], grammar: Any, text: str, must_read: bool = False
) -> None:
    """``read(text)`` is textX's tree, or None where textX refuses the text (or where
    ``must_read`` is false: the reader may leave a text to textX)."""
    found = read(text)
    expected = textx_tree(grammar, text)
    if found is None:
        assert not must_read, f"the reader refused a text textX reads as {expected!r}"
        return
    assert not isinstance(expected, str), f"the reader took a text textX refuses: {expected}"
    assert difference(expected, found) is None, difference(expected, found)


TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*|\d+(\.\d+)?|\"[^\"]*\"|->|<-|[{}:=.,()\[\]+*/-]")


def mutated_texts(
    paths: list[Path], substitutes: tuple[str, ...], count: int, seed: int = 17
) -> list[str]:
    """A fixed random sample of ``count`` texts of ``paths`` with a line deleted or
    doubled, or a token deleted or replaced by one of ``substitutes``."""
    rng = random.Random(seed)
    cases = []
    for path in paths:
        lines = path.read_text(encoding="utf-8").split("\n")
        for i, line in enumerate(lines):
            cases.append("\n".join(lines[:i] + lines[i + 1 :]))
            cases.append("\n".join(lines[: i + 1] + lines[i:]))
            for token in TOKEN.finditer(line):
                new = line[: token.start()] + rng.choice(substitutes) + line[token.end() :]
                cases.append("\n".join([*lines[:i], new, *lines[i + 1 :]]))
    return rng.sample(cases, min(count, len(cases)))


def grammar_patterns(grammar: Any, rule: str) -> list[tuple[str, int]]:
    """The regular expressions (pattern, flags) textX compiled for ``rule``, in order."""
    found, stack, seen = [], [grammar[rule]._tx_peg_rule], set()
    while stack:
        expression = stack.pop()
        if id(expression) in seen:
            continue
        seen.add(id(expression))
        if isinstance(expression, RegExMatch):
            found.append((expression.regex.pattern, expression.regex.flags))
        stack.extend(reversed(getattr(expression, "nodes", [])))
    return found
