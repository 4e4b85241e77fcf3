"""The fast .tsm reader (spl.dsl.tsm_reader) reads exactly what textX reads (issue 17).

Where the reader takes a text, its tree must equal textX's object for object: class
name, every attribute of the rule, ``_tx_position``; where textX refuses a text, the
reader must refuse it too (textX then words the syntax error). Checked on every
shipped .tsm, on mutations of them, on generated lines and on texts built for the
grammar's corners (comments between tokens, settings in any order, keywords as names,
the nesting bound).
"""

from __future__ import annotations

import random
import re
from pathlib import Path
from typing import Any

import pytest
from arpeggio import RegExMatch
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis_budget import examples
from model_mutations import mutate, mutations
from random_lines import line_specs, tsm_text
from textx import TextXSyntaxError

from spl.diagnostics import ModelError
from spl.dsl import parse_tree, tsm, tsm_expression_reader, tsm_reader, tsm_tree

ROOT = Path(__file__).resolve().parent.parent
SHIPPED = sorted(p for base in ("product_lines", "tests") for p in (ROOT / base).rglob("*.tsm"))
TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*|\d+(\.\d+)?|\"[^\"]*\"|->|<-|[{}:=.,()\[\]+*/-]")
SUBSTITUTES = ("", "Zz", "2", '"/a b"', "optional", "-", "(", "node", "//", "/*", "é", "{", "->")


def textx_tree(text: str) -> Any:
    """textX's tree of ``text``, or the name of its refusal."""
    try:
        return tsm._grammar().model_from_str(text)
    except TextXSyntaxError:
        return "syntax error"
    except RecursionError:
        return "too deep"


def difference(expected: Any, found: Any, path: str = "System") -> str | None:
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


def assert_reads_as_textx(text: str, must_read: bool = False) -> None:
    found = tsm_reader.read(text)
    expected = textx_tree(text)
    if found is None:
        assert not must_read, f"the reader refused a text textX reads as {expected!r}"
        return
    assert not isinstance(expected, str), f"the reader took a text textX refuses: {expected}"
    assert difference(expected, found) is None, difference(expected, found)


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_shipped_model_is_read_as_textx_reads_it(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    assert_reads_as_textx(text, must_read=not isinstance(textx_tree(text), str))


def test_mutated_shipped_models_are_read_as_textx_reads_them() -> None:
    """Lines deleted and doubled, tokens deleted or replaced: a fixed random sample."""
    rng = random.Random(17)
    cases = []
    for path in SHIPPED:
        lines = path.read_text(encoding="utf-8").split("\n")
        for i, line in enumerate(lines):
            cases.append("\n".join(lines[:i] + lines[i + 1 :]))
            cases.append("\n".join(lines[: i + 1] + lines[i:]))
            for token in TOKEN.finditer(line):
                new = line[: token.start()] + rng.choice(SUBSTITUTES) + line[token.end() :]
                cases.append("\n".join([*lines[:i], new, *lines[i + 1 :]]))
    for text in rng.sample(cases, 600):
        assert_reads_as_textx(text)


@settings(max_examples=examples(40), deadline=None)
@given(line_specs(), st.data())
def test_generated_and_mutated_lines_are_read_as_textx_reads_them(spec, data) -> None:
    text = tsm_text(spec)
    assert_reads_as_textx(text, must_read=True)
    assert_reads_as_textx(mutate(text, data.draw(mutations(text))))


CORNERS = {
    "comments between every token": """
        /* a */ system /**/ S // c
        robot // c
        container /* c */ R /* c */ { endpoint /* c */ url /* c */ "wss://x:1/"
          topic/**/T/**/:/**/std_msgs/String/**/name/**/"/t"
          optional/**/node/**/N/**/sharing/**/public/**/{/**/publishes/**/p/**/->/**/T/**/}
        } // end""",
    "cloud settings and endpoint settings in any order": """
        cloud container C bandwidth 5 memory 4 group "g" cpu 2 size 1 { namespace "/n" }
        robot container R { endpoint password env "PW" user "u" robot_id "r1" url "wss://h/" }
        robot container Q { endpoint password "secret" }
        robot container P { endpoint }""",
    "keywords as names, names starting with keywords": """
        system node
        robot container container {
            topic topic : a/B
            topic nodes : a/B name "/x"
            node node { param param : int = -3  param p2 : yaml = "{a: 1}"
                        param p3 : bool = false  param p4 : double = .5e3
                        subscribes subscribes <- topic  publishes calls : a/B
                        calls calls : s/S  calls c2 -> other.srv  provides srv : s/S name "/s" }
            optional writer w : D to C.S <- topic
            reader r : D from C.S -> topic every 1.5 s {
                implementation p/e args "-x" param q : int }
        }
        bridge container.topic -> X.topic
        bridge A.n.c -> B.m.s""",
    "data and expressions": """
        data D { a : double  b : int  c : string  d : bool }
        transform T : D -> D {
            a = -a * (b + 2) / 3 % 4 - -1.5e2
            b = if(a <= 1 and not b >= 2 or c == "x", max(a, b, 3), abs(prev.a))
            c = a != b  d = a < b  c = a > b  a = x[1]  b = f()  c = .5 + 1. + 1e3 + true + false
            d = not not d  a = next.b.c  b = order + android + notable
        }
        cloud container C { optional store S { raw D refined D by T every 2 s } }""",
    "nothing but a name": "system S",
    "unicode after a keyword": "robot container R { nodeé }",
    "unicode in a name": "robot container Ré { }",
    "a topic marked optional": "robot container R { optional topic T : a/B }",
    "trailing comma in a call": "data D { a : double } transform T : D -> D { a = max(a, ) }",
    "unclosed comment": "robot container R { } /* never closed",
    "a number glued to a name": "cloud container C size 12x { }",
    "only blanks and comments": "  // nothing\n /* here */ ",
}


@pytest.mark.parametrize("text", CORNERS.values(), ids=CORNERS.keys())
def test_corners_of_the_grammar_are_read_as_textx_reads_them(text: str) -> None:
    assert_reads_as_textx(text)


def test_valid_corners_are_read_by_the_reader_itself() -> None:
    for label in list(CORNERS)[:5]:
        assert tsm_reader.read(CORNERS[label]) is not None, label


def nested(depth: int) -> str:
    inner = "(" * depth + "a" + ")" * depth
    return f"data D {{ a : double }} transform T : D -> D {{ a = {inner} }}"


def test_expressions_nested_deeper_than_the_bound_are_left_to_textx() -> None:
    bound = tsm_expression_reader.MAX_DEPTH
    assert tsm_reader.read(nested(bound - 1)) is not None  # the assignment is one level
    assert tsm_reader.read(nested(bound)) is None
    assert_reads_as_textx(nested(bound - 1), must_read=True)
    with pytest.raises(ModelError, match="nested too deeply"):
        tsm.parse_text(nested(60))


def test_the_readers_terminals_are_the_grammars() -> None:
    """The regular expressions, whitespace and comments textX compiled from tsm.tx."""
    grammar = tsm._grammar()

    def patterns(rule: str) -> list[tuple[str, int]]:
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

    terminals = {
        "Ident": tsm_tree.IDENT,
        "RosType": tsm_tree.ROS_TYPE,
        "QuotedString": tsm_tree.QUOTED_STRING,
        "UnsignedNumber": tsm_tree.UNSIGNED_NUMBER,
        "SignedNumber": tsm_tree.SIGNED_NUMBER,
        "Boolean": tsm_tree.BOOLEAN,
        "Int": tsm_tree.INT,
    }
    for rule, regex in terminals.items():
        assert patterns(rule) == [(regex.pattern, regex.flags)], rule
    assert [pattern for pattern, _ in patterns("Comment")] == list(parse_tree.COMMENTS)
    assert grammar._parser_blueprint.ws == parse_tree.WHITESPACE
    assert grammar.autokwd and grammar._parser_blueprint.skipws


def test_parse_text_gives_the_same_model_and_errors_through_either_parser(monkeypatch) -> None:
    """The builder cannot tell the trees apart: a file built from the reader's tree and
    from textX's prints the same and fails with the same messages."""
    from spl.dsl.tsm_printer import print_model

    broken = CORNERS["keywords as names, names starting with keywords"]
    texts = [p.read_text(encoding="utf-8") for p in SHIPPED[:6]] + [broken]

    def outcome(text: str) -> str:
        try:
            return print_model(tsm.parse_text(text, "m.tsm"))
        except ModelError as exc:
            return "\n".join(map(str, exc.diagnostics))

    fast = [outcome(text) for text in texts]
    monkeypatch.setattr(tsm_reader, "read", lambda text: None)
    assert [outcome(text) for text in texts] == fast
    assert "error" in fast[-1]
