"""The fast .tsm reader (spl.dsl.tsm.reader) reads exactly what textX reads.

Where the reader takes a text, its tree must equal textX's object for object: class
name, every attribute of the rule, ``_tx_position``; where textX refuses a text, the
reader must refuse it too (textX then words the syntax error). Checked on every
shipped .tsm, on mutations of them, on generated lines and on texts built for the
grammar's corners (comments between tokens, settings in any order, keywords as names,
the nesting bound).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st

from spl.core.diagnostics import ModelError
from spl.dsl import parse_tree
from spl.dsl.tsm import (
    expression_reader as tsm_expression_reader,
    language as tsm,
    reader as tsm_reader,
    syntax_excerpt as tsm_syntax_excerpt,
    tree as tsm_tree,
)

from support.hypothesis_budget import examples
from support.model_mutations import mutate, mutations
from support.random_lines import line_specs, tsm_text
from support.textx_trees import (
    ROOT,
    assert_reads_as_textx as reads_as_textx,
    grammar_patterns,
    mutated_texts,
    shipped,
    textx_tree,
)

SHIPPED = shipped(".tsm")
SUBSTITUTES = ("", "Zz", "2", '"/a b"', "optional", "-", "(", "node", "//", "/*", "é", "{", "->")


def assert_reads_as_textx(text: str, must_read: bool = False) -> None:
    reads_as_textx(tsm_reader.read, tsm._grammar(), text, must_read)


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_shipped_model_is_read_as_textx_reads_it(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    assert_reads_as_textx(text, must_read=not isinstance(textx_tree(tsm._grammar(), text), str))


def test_mutated_shipped_models_are_read_as_textx_reads_them() -> None:
    """Lines deleted and doubled, tokens deleted or replaced: a fixed random sample."""
    for text in mutated_texts(SHIPPED, SUBSTITUTES, 600):
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
    "inputs fed from outside (docs/tsm.md)": """
        robot container R { topic T : a/B
            node external { subscribes external <- T external "the bring-up's driver"
                            subscribes s2 : a/B external ""  calls c : s/S external "x"
                            calls c2 -> external.srv external "y"  provides srv : s/S } }""",
    "actions, and action as a name (docs/tsm.md)": """
        robot container R { node N {
            provides action move_base : move_base_msgs/MoveBase name "/move_base"
            provides action : std_srvs/Empty  provides action action : a/B
            calls action goal : move_base_msgs/MoveBase -> N.move_base external "x"
            calls action -> N.action  calls action g2 -> N.move_base  calls action : s/S
            calls action/**/g3/**/: a/B  calls actions : s/S  provides actions : s/S } }""",
    "an action statement cut short": "robot container R { node N { provides action x } }",
    "an action called by a service's arrow": "robot container R { node N { calls action -> } }",
    "external on a publisher": 'robot container R { node N { publishes p : a/B external "x" } }',
    "external without its reason": "robot container R { node N { subscribes s : a/B external } }",
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
    for label in [
        *list(CORNERS)[:5],
        "inputs fed from outside (docs/tsm.md)",
        "actions, and action as a name (docs/tsm.md)",
    ]:
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
        return grammar_patterns(grammar, rule)

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


def test_a_rule_is_declared_once_for_the_type_checker_and_the_reader() -> None:
    """A rule declared as a class (tsm_tree) is, at run time, the tuple the reader builds
    and textX's attributes are compared with: its annotated fields in order, position
    first and also read as ``_tx_position``."""

    class Sample(parse_tree.Rule):
        position: int
        name: str
        members: list[str]

    made = Sample(4, "a", ["b"])
    assert isinstance(made, tuple) and type(made).__name__ == "Sample"
    assert Sample._fields == ("position", "name", "members")
    assert (made.position, made._tx_position, made.name, made.members) == (4, 4, "a", ["b"])
    assert tsm_tree.Index(7, None).index is None  # a field named like a tuple method
    with pytest.raises(TypeError, match="takes 3 values"):
        Sample(4, "a")
    with pytest.raises(TypeError, match="first field is its position"):

        class Unplaced(parse_tree.Rule):
            name: str


def test_parse_text_gives_the_same_model_and_errors_through_either_parser(monkeypatch) -> None:
    """The builder cannot tell the trees apart: a file built from the reader's tree and
    from textX's prints the same and fails with the same messages."""
    from spl.dsl.tsm.printer import print_model

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


def whole_and_excerpt_errors(text: str) -> tuple[str, str] | None:
    """The syntax error textX words from the whole ``text`` and from the reader's
    excerpt of it; None where the reader reads the text or textX reads the excerpt."""
    from textx import TextXSyntaxError

    from spl.dsl.tsm.syntax import syntax_diagnostic

    excerpt = tsm_syntax_excerpt.error_excerpt(text)
    if excerpt is None:
        return None
    assert excerpt.count("\n") == text.count("\n")
    worded = []
    for parsed in (text, excerpt):
        try:
            tsm._grammar().model_from_str(parsed)
        except TextXSyntaxError as exc:
            worded.append(str(syntax_diagnostic(exc, text, "m.tsm")))
        else:
            worded.append(None)
    if worded[1] is None:  # the reader's own bound: the whole text is parsed
        return None
    return worded[0], worded[1]


def test_syntax_errors_are_worded_from_the_excerpt_as_from_the_whole_text() -> None:
    """The excerpt textX reads to word a syntax error (every declaration read before the
    one in error left out) gives the same line, column and expectation as the whole
    file, on the mutation corpus."""
    compared = 0
    for text in mutated_texts(SHIPPED, SUBSTITUTES, 600, seed=5):
        errors = whole_and_excerpt_errors(text)
        if errors is not None:
            assert errors[1] == errors[0], text
            compared += 1
    assert compared > 200


@settings(max_examples=examples(40), deadline=None)
@given(line_specs(), st.data())
def test_syntax_errors_of_generated_lines_are_worded_from_the_excerpt_alike(spec, data) -> None:
    text = mutate(tsm_text(spec), data.draw(mutations(tsm_text(spec))))
    errors = whole_and_excerpt_errors(text)
    if errors is not None:
        assert errors[1] == errors[0]


def test_a_syntax_error_late_in_a_large_file_is_worded_from_a_small_excerpt() -> None:
    """Only the declaration in error (and the one before, emptied) reach textX."""
    nodes = "".join(
        f"    node N{i} {{\n        implementation pkg/exe\n        publishes out -> T\n    }}\n"
        for i in range(300)
    )
    text = (
        f"robot container R {{\n    topic T : std_msgs/String\n{nodes}    node Bad {{ nope }}\n}}\n"
    )
    excerpt = tsm_syntax_excerpt.error_excerpt(text)
    assert excerpt is not None and "N0" not in excerpt and "N298" not in excerpt
    errors = whole_and_excerpt_errors(text)
    assert errors is not None and errors[0] == errors[1]
    assert errors[0].startswith("m.tsm:1203:16: error: syntax error: expected")


def test_an_error_after_a_large_container_keeps_the_container_but_not_its_nodes() -> None:
    nodes = "".join(
        f"    node N{i} {{\n        implementation pkg/exe\n    }}\n" for i in range(50)
    )
    text = f"robot container R {{\n{nodes}}}\n}} stray\n"
    excerpt = tsm_syntax_excerpt.error_excerpt(text)
    assert excerpt is not None and "robot container R" in excerpt and "N7" not in excerpt
    errors = whole_and_excerpt_errors(text)
    assert errors is not None and errors[0] == errors[1]
    assert errors[0] == (
        "m.tsm:153:1: error: syntax error: expected 'bridge', 'cloud', 'data', 'robot', "
        "'transform', end of file, found '}'"
    )
