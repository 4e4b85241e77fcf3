"""The fast .fm reader (spl.dsl.fm.reader) reads exactly what textX reads.

Where the reader takes a text, its tree equals textX's object for object (class name,
every attribute of the rule, ``_tx_position``); where textX refuses a text, the reader
refuses it too and textX words the syntax error. Checked on every shipped .fm, on
mutations of them, on feature models generated over the whole grammar (and mutated),
on the corners of the grammar, and for capability conditions read on their own (as
UVL and FeatureIDE files carry them).
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings, strategies as st

from spl.core.diagnostics import ModelError
from spl.dsl import parse_tree
from spl.dsl.fm import capability as fm_capability, language as fm, reader as fm_reader
from spl.dsl.fm.printer import print_model

from support.hypothesis_budget import examples
from support.model_mutations import mutate, mutations
from support.textx_trees import (
    ROOT,
    assert_reads_as_textx,
    grammar_patterns,
    mutated_texts,
    shipped,
    textx_tree,
)

SHIPPED = shipped(".fm")
SUBSTITUTES = ("", "Zz", "2", '"x"', "optional", "xor", "{", "}", "(", "and", "//", "/*", "é")


def reads_as_textx(text: str, must_read: bool = False) -> None:
    assert_reads_as_textx(fm_reader.read, fm._grammar(), text, must_read)


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_shipped_model_is_read_as_textx_reads_it(path) -> None:
    text = path.read_text(encoding="utf-8")
    reads_as_textx(text, must_read=not isinstance(textx_tree(fm._grammar(), text), str))


def test_mutated_shipped_models_are_read_as_textx_reads_them() -> None:
    """Lines deleted and doubled, tokens deleted or replaced: a fixed random sample."""
    for text in mutated_texts(SHIPPED, SUBSTITUTES, 400):
        reads_as_textx(text)


# -- feature models drawn over the whole grammar -------------------------------------------
NAMES = st.sampled_from(["A", "B", "Cam", "capability", "root", "orX", "notable", "x_1"])
LITERALS = st.sampled_from(['"s"', '"a\\"b"', "true", "false", "-1.5", ".5e3", "7", "-0"])
CONDITIONS = st.tuples(
    st.sampled_from(["onboard_pc", "base", "compute.cores", "has_x", "andy"]),
    st.sampled_from(["", " = ", " != ", " >= ", " <= ", " has ", "="]),
    st.sampled_from(['"youbot"', "4", "2.5", "true", "-1"]),
).map(lambda c: c[0] if not c[1] else "".join(c))


@st.composite
def features(draw, depth: int = 0) -> str:
    abstract = draw(st.sampled_from(["", "abstract "]))
    text = abstract + draw(NAMES)
    if depth < 3 and draw(st.integers(0, 3)) == 0:
        text += " " + draw(groups(depth + 1))
    if draw(st.booleans()):
        items = draw(st.lists(body_items(depth + 1), max_size=4 if depth < 3 else 1))
        text += " { " + " ".join(items) + " }"
    return text


@st.composite
def groups(draw, depth: int) -> str:
    members = " ".join(draw(st.lists(features(depth), min_size=1, max_size=3)))
    head = draw(st.sampled_from(["xor", "or", "group [1]", "group [0..*]", "group [2..3]"]))
    return f"{head} {{ {members} }}"


@st.composite
def body_items(draw, depth: int) -> str:
    kind = draw(st.integers(0, 6 if depth < 3 else 3))
    if kind == 0:
        name = draw(st.sampled_from(["a", "weight", "sharing"]))
        attribute_type = draw(st.sampled_from(["int", "double", "string", "bool"]))
        return f"attribute {name} : {attribute_type} = {draw(LITERALS)}"
    if kind == 1:
        return "sharing " + draw(st.sampled_from(["public", "protected", "private"]))
    if kind == 2:
        return "capability " + " and ".join(draw(st.lists(CONDITIONS, min_size=1, max_size=3)))
    if kind == 3:
        return draw(st.sampled_from(["mandatory", "optional"])) + " " + draw(NAMES)
    if kind == 4:
        return draw(st.sampled_from(["mandatory", "optional"])) + " " + draw(features(depth))
    if kind == 5:
        members = " ".join(draw(st.lists(features(depth), min_size=1, max_size=2)))
        return draw(st.sampled_from(["mandatory", "optional"])) + f" {{ {members} }}"
    return draw(groups(depth))


@st.composite
def formulas(draw, depth: int = 0) -> str:
    if depth > 2 or draw(st.integers(0, 2)) == 0:
        return draw(st.sampled_from(["A", "B", "Cam", "x_1"]))
    kind = draw(st.integers(0, 2))
    if kind == 0:
        return "not " + draw(formulas(depth + 1))
    if kind == 1:
        return "(" + draw(formulas(depth + 1)) + ")"
    operator = draw(st.sampled_from(["and", "or", "=>", "<=>", "requires", "excludes"]))
    return f"{draw(formulas(depth + 1))} {operator} {draw(formulas(depth + 1))}"


@st.composite
def feature_models(draw) -> str:
    text = f"// drawn\nfeature model M\nroot {draw(features())}\n"
    if draw(st.booleans()):
        text += "constraints {\n" + "\n".join(draw(st.lists(formulas(), max_size=4))) + "\n}\n"
    return text


@settings(max_examples=examples(60), deadline=None)
@given(feature_models(), st.data())
def test_generated_and_mutated_models_are_read_as_textx_reads_them(text, data) -> None:
    reads_as_textx(text)
    if not isinstance(textx_tree(fm._grammar(), text), str):
        reads_as_textx(text, must_read=True)
    reads_as_textx(mutate(text, data.draw(mutations(text))))


CORNERS = {
    "comments between every token": """/* a */ feature // c
        model /**/ M root /**/ abstract /**/ R /**/ xor /**/ { /**/ A /**/ B /**/ } /**/ {
        attribute /**/ a /**/ : /**/ int /**/ = /**/ -3 capability /**/ x /**/ >= /**/ 2
        /**/ and /**/ y } constraints /**/ { /**/ ( /**/ A /**/ ) /**/ => /**/ B /**/ }""",
    "keywords run into names": """feature model M root R { optionalA mandatoryB
        optional xorA optional orB optional groupC optional notX optional andY }""",
    "a capability operator '=' before '>'": "feature model M root R { capability a => 1 }",
    "capability keys and literals": """feature model M root R { capability a.b.c has "x"
        and d != false and e <= -1.5 and f = .5e3 and g }""",
    "has as a capability key": "feature model M root R { capability a and has }",
    "a constraint starting with a parenthesis": """feature model M root R { optional A
        optional B } constraints { (A) ((A or B)) not (A) A => B => A A <=> B <=> A }""",
    "cardinality bounds": """feature model M root R { group [1] { A } group [0..*] { B }
        group [2..3] { C D } group [1..] { E } }""",
    "a group after a closed child": "feature model M root R { optional A { } xor { B C } }",
    "a kind block": "feature model M root R { mandatory { A B } optional { C } mandatory { } }",
    "abstract as a name": "feature model M root abstract { }",
    "unicode after a name": "feature model M root Ré { }",
    "unicode after a keyword": "feature model M root R { optionalé A }",
    "an unclosed comment": "feature model M root R /* never closed",
    "nothing": " // only a comment\n",
    "a number glued to a name": "feature model M root R { attribute a : int = 12x }",
    "strings with escapes": r'feature model M root R { attribute a : string = "a\"b\\c\n" }',
    "constraints left empty": "feature model M root R constraints { }",
}


@pytest.mark.parametrize("text", CORNERS.values(), ids=CORNERS.keys())
def test_corners_of_the_grammar_are_read_as_textx_reads_them(text: str) -> None:
    reads_as_textx(text)


def test_valid_corners_are_read_by_the_reader_itself() -> None:
    for label in ("comments between every token", "capability keys and literals"):
        assert fm_reader.read(CORNERS[label]) is not None, label
        reads_as_textx(CORNERS[label], must_read=True)


def nested_features(depth: int) -> str:
    text = "X0"
    for level in range(1, depth):
        text = f"X{level} {{ optional {text} }}"
    return f"feature model M root {text}"


def nested_formula(depth: int) -> str:
    inner = "(" * (depth - 1) + "A" + ")" * (depth - 1)
    return f"feature model M root R {{ optional A }} constraints {{ {inner} }}"


@pytest.mark.parametrize("nested", [nested_features, nested_formula])
def test_nesting_deeper_than_the_bound_is_left_to_textx(nested) -> None:
    bound = fm_reader.MAX_DEPTH
    assert fm_reader.read(nested(bound)) is not None
    assert fm_reader.read(nested(bound + 1)) is None
    reads_as_textx(nested(bound), must_read=True)
    with pytest.raises(ModelError, match="nested too deeply"):
        fm.parse_text(nested(200))


def test_the_readers_terminals_are_the_grammars() -> None:
    grammar = fm._grammar()
    terminals = {
        "FeatureName": fm_reader.FEATURE_NAME,
        "Ident": fm_reader.IDENT,
        "Natural": fm_reader.NATURAL,
        "BoolWord": fm_reader.BOOL_WORD,
        "DoubleNumber": fm_reader.DOUBLE_NUMBER,
        "IntNumber": fm_reader.INT_NUMBER,
        "QuotedString": fm_reader.QUOTED_STRING,
        "CapabilityQuoted": fm_reader.CAPABILITY_QUOTED,
        "CapabilityBoolWord": fm_reader.BOOL_WORD,
        "CapabilityDoubleNumber": fm_reader.DOUBLE_NUMBER,
        "CapabilityIntNumber": fm_reader.INT_NUMBER,
        "CapabilityKey": fm_reader.CAPABILITY_KEY,
    }
    for rule, regex in terminals.items():
        assert grammar_patterns(grammar, rule) == [(regex.pattern, regex.flags)], rule
    comments = [pattern for pattern, _ in grammar_patterns(grammar, "Comment")]
    assert comments == list(parse_tree.COMMENTS)
    assert grammar._parser_blueprint.ws == parse_tree.WHITESPACE
    assert grammar.autokwd and grammar._parser_blueprint.skipws


CAPABILITY_TEXTS = (
    'base = "youbot" and onboard_pc',
    "  compute.cores >= 4 and memory <= 2.5 and gpu != false and x has -1  ",
    "a and",
    "a /* no comments here */",
    "has",
    'a = "it\'s"',
    "a => 1",
    "",
)


@pytest.mark.parametrize("text", CAPABILITY_TEXTS)
def test_capability_conditions_alone_are_read_as_textx_reads_them(text: str) -> None:
    grammar = fm_capability._capability_grammar()
    assert_reads_as_textx(fm_reader.read_capabilities, grammar, text)
    if not isinstance(textx_tree(grammar, text), str):
        assert_reads_as_textx(fm_reader.read_capabilities, grammar, text, must_read=True)


def test_parse_text_gives_the_same_model_and_errors_through_either_parser(monkeypatch) -> None:
    """The builder cannot tell the trees apart: a file built from the reader's tree and
    from textX's prints the same and fails with the same messages (located alike)."""
    broken = """feature model M root abstract R { attribute a : int = "x" optional R
        capability c >= "s" group [3..1] { A } } constraints { Ghost or (A => R) }"""
    texts = [p.read_text(encoding="utf-8") for p in SHIPPED] + [broken, *CORNERS.values()]

    def outcome(text: str) -> str:
        try:
            return print_model(fm.parse_text(text, "m.fm"))
        except ModelError as exc:
            return "\n".join(map(str, exc.diagnostics))

    fast = [outcome(text) for text in texts]
    monkeypatch.setattr(fm_reader, "read", lambda text: None)
    assert [outcome(text) for text in texts] == fast
    assert "m.fm:1:55: error" in fast[len(SHIPPED)]


def test_capability_text_gives_the_same_conditions_and_errors_through_either_parser(
    monkeypatch,
) -> None:
    def outcome(text: str) -> str:
        try:
            conditions = fm_capability.parse_capability_conditions(text, None)
            return repr([(c.key, c.operator, c.value, c.valueType) for c in conditions])
        except ModelError as exc:
            return "\n".join(d.message for d in exc.diagnostics)

    fast = [outcome(text) for text in CAPABILITY_TEXTS]
    monkeypatch.setattr(fm_reader, "read_capabilities", lambda text: None)
    assert [outcome(text) for text in CAPABILITY_TEXTS] == fast
    assert "syntax error" in fast[2]
