"""The fast .rm reader (spl.dsl.rm.reader) reads exactly what textX reads.

Where the reader takes a text, its tree equals textX's object for object (class name,
every attribute of the rule, ``_tx_position``); where textX refuses a text, the reader
refuses it too and textX words the syntax error. rm.tx is not built with autokwd, so
the corners include keywords running into names. Checked on every shipped .rm,
mutations of them, generated lines (and mutated), and through ``rm.parse_text``.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st

from spl.core.diagnostics import ModelError
from spl.dsl import parse_tree
from spl.dsl.rm import language as rm, reader as rm_reader

from support.hypothesis_budget import examples
from support.model_generator import generated_lines
from support.model_mutations import mutate, mutations
from support.textx_trees import (
    ROOT,
    assert_reads_as_textx,
    grammar_patterns,
    mutated_texts,
    shipped,
    textx_tree,
)

SHIPPED = shipped(".rm")
SUBSTITUTES = ("", "Zz", "2", '"x"', "not", "to", "{", "}", ".", ",", "->", "//", "/*", "é")


def reads_as_textx(text: str, must_read: bool = False) -> None:
    assert_reads_as_textx(rm_reader.read, rm._grammar(), text, must_read)


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_shipped_model_is_read_as_textx_reads_it(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    reads_as_textx(text, must_read=not isinstance(textx_tree(rm._grammar(), text), str))


def test_mutated_shipped_models_are_read_as_textx_reads_them() -> None:
    """Lines deleted and doubled, tokens deleted or replaced: a fixed random sample."""
    for text in mutated_texts(SHIPPED, SUBSTITUTES, 400):
        reads_as_textx(text)


@settings(max_examples=examples(60), deadline=None)
@given(generated_lines(), st.data())
def test_generated_and_mutated_models_are_read_as_textx_reads_them(files, data) -> None:
    text = files["gen.rm"]  # mostly right: a few statements are drawn broken
    reads_as_textx(text, must_read=not isinstance(textx_tree(rm._grammar(), text), str))
    reads_as_textx(mutate(text, data.draw(mutations(text))))


HEADER = 'resolution model M tsm "m.tsm" fm "m.fm"\n'
CORNERS = {
    "comments between every token": """/* a */ resolution // c
        model /**/ M /**/ tsm /**/ "m.tsm" /**/ fm /**/ "m.fm" /**/ when /**/ F /**/ not
        /**/ selected /**/ { /**/ require /**/ A /**/ . /**/ b /**/ , /**/ c
        connect /**/ x /**/ to /**/ new /**/ topic /**/ T /**/ : /**/ a/B /**/ name "/t"
        parameter /**/ N.p /**/ = /**/ feature /**/ F /**/ . /**/ a /**/ } // end""",
    "keywords run into names": HEADER
    + """whenF notselected { requireA, B.c connect bridgeA.b to topic T
        connect bridge A.b -> C.d connectx to servery.z migrateN toR
        implementationN = p/e parameterN.q = true }""",
    "every statement": HEADER
    + """when F selected { require A
        implementation N = pkg/exe implementation N.M = p1/e.x-y
        connect A.b to topic C.t connect A.b to new topic T : m/T
        connect A.c to server B.s connect bridge A.b -> B.c
        parameter N.p = "s" parameter N.q = 'single \\' quote' parameter N.r = false
        parameter N.s = -1.5e3 parameter N.t = +.5 parameter N.u = 7
        migrate N to C } when G not selected { }""",
    "strings with escapes": "resolution model M tsm \"a\\\"b\" fm 'c\\'d' when F selected { }",
    "a string over lines": 'resolution model M tsm "a\nb" fm "x"',
    "a number glued to a name": HEADER + "when F selected { parameter N.p = 12x }",
    "unicode in a name": HEADER + "when Fé selected { }",
    "a dangling dot": HEADER + "when F selected { require A. }",
    "a dangling comma": HEADER + "when F selected { require A, }",
    "an unclosed comment": HEADER + "/* never closed",
    "nothing": "",
}


@pytest.mark.parametrize("text", CORNERS.values(), ids=CORNERS.keys())
def test_corners_of_the_grammar_are_read_as_textx_reads_them(text: str) -> None:
    reads_as_textx(text)


def test_valid_corners_are_read_by_the_reader_itself() -> None:
    for label in list(CORNERS)[:4]:
        reads_as_textx(CORNERS[label], must_read=True)


def test_the_readers_terminals_are_the_grammars() -> None:
    grammar = rm._grammar()
    terminals = {"Ident": rm_reader.IDENT, "RosType": rm_reader.ROS_TYPE}
    terminals["Number"] = rm_reader.NUMBER
    for rule, regex in terminals.items():
        assert grammar_patterns(grammar, rule) == [(regex.pattern, regex.flags)], rule
    string = next(p for p in grammar_patterns(grammar, "StringValue"))
    assert string == (rm_reader.STRING.pattern, rm_reader.STRING.flags)
    comments = [pattern for pattern, _ in grammar_patterns(grammar, "Comment")]
    assert comments == list(parse_tree.COMMENTS)
    assert grammar._parser_blueprint.ws == parse_tree.WHITESPACE
    assert not grammar.autokwd and grammar._parser_blueprint.skipws


def test_load_gives_the_same_model_and_errors_through_either_parser(
    monkeypatch, tmp_path: Path
) -> None:
    """The builder cannot tell the trees apart: every shipped .rm, and broken ones
    (a missing .tsm, unknown names), load alike and fail with the same located
    messages through either parser."""
    (tmp_path / "m.fm").write_text("feature model M root R { optional F }\n", encoding="utf-8")
    broken = [
        tmp_path / "missing.rm",
        tmp_path / "unknown.rm",
    ]
    broken[0].write_text('// a header after a comment\nresolution model M tsm "no.tsm" fm "m.fm"')
    broken[1].write_text(
        'resolution model M tsm "m.tsm" fm "m.fm"\n'
        "when Ghost selected { require Nobody }\nwhen F selected { migrate A.b to X }\n"
    )
    (tmp_path / "m.tsm").write_text("robot container R { node A { } }\n", encoding="utf-8")

    def outcome(path: Path) -> str:
        try:
            files = rm.load(path)
        except ModelError as exc:
            return "\n".join(map(str, exc.diagnostics))
        elements = [
            (e.srcLine, e.srcCol, e.feature.name, [t.srcLine for t in e.transformations])
            for e in files.rm.elements
        ]
        return repr((files.rm.name, files.rm.tsmPath, files.rm.fmPath, elements))

    paths = [*SHIPPED, *broken]
    fast = [outcome(path) for path in paths]
    monkeypatch.setattr(rm_reader, "read", lambda text: None)
    assert [outcome(path) for path in paths] == fast
    assert "missing.rm:2:20: error: tsm file" in fast[-2]  # at `tsm "no.tsm"`
    assert "unknown.rm:2:1: error: unknown feature Ghost" in fast[-1]
