"""The grammars are the one source of the languages' keywords (spl.dsl.grammar_keywords).

Its reading of ``dsl/*.tx`` is checked against the metamodel textX compiles from the
same files (every keyword, and the words each rule can start with); every set of
keywords kept elsewhere is derived from it or compared with it here: the language
server's statement and completion sets, the words a feature or a data field may not be
called, the sharing modes the resolver checks, and the fast readers' dispatch tables.
A keyword added to a grammar reaches the derived sets (checked on edited copies of the
grammars); one that a reader does not know fails
``test_every_keyword_is_known_to_the_fast_reader_of_its_grammar``. The TextMate grammars
of the VS Code extension are compared in ``tests/cli/test_lsp_editors.py``.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import arpeggio
import pytest

from spl.dsl import grammar_keywords
from spl.dsl.fm import capability as fm_capability, language as fm, vocabulary
from spl.dsl.rm import language as rm
from spl.dsl.tsm import (
    interface_reader as tsm_interface_reader,
    language as tsm,
    reader as tsm_reader,
    transforms,
)
from spl.lsp import completion, occurrences

ROOT = Path(__file__).resolve().parents[2]
DSL = ROOT / "src" / "spl" / "dsl"
LANGUAGES = {
    "tsm": tsm._grammar,
    "fm": fm._grammar,
    "rm": rm._grammar,
    "capability": fm_capability._capability_grammar,
}
# The hand-written fast reader of each grammar (with the modules holding its rules).
READERS = {
    "tsm": [
        "tsm/reader.py",
        "tsm/interface_reader.py",
        "tsm/expression_reader.py",
        "tsm/tree.py",
        # the interface statements' keywords, which interface_reader.py reads from the
        # registry of interface kinds (docs/architecture.md, "Interface kinds")
        "../metamodels/interface_kinds.py",
    ],
    "fm": ["fm/reader.py"],
    "rm": ["rm/reader.py"],
}


# -- textX's compiled grammar as the oracle ---------------------------------------------
def textx_rules(language: str) -> dict[str, Any]:
    """The parsing expression of each rule of textX's metamodel of ``language``."""
    found: dict[str, Any] = {}
    seen: set[int] = set()
    stack = [LANGUAGES[language]()._parser_blueprint.parser_model]
    while stack:
        expression = stack.pop()
        if id(expression) in seen:
            continue
        seen.add(id(expression))
        if expression.rule_name and not expression.rule_name.startswith("__"):
            found.setdefault(expression.rule_name, expression)
        stack.extend(getattr(expression, "nodes", []))
    return found


def textx_keyword(expression: Any) -> str | None:
    """The keyword a match is (``autokwd`` grammars compile keywords to regexes)."""
    if isinstance(expression, arpeggio.Match) and not isinstance(expression, arpeggio.EndOfFile):
        text = expression.to_match
        return text if grammar_keywords.is_word(text) else None
    return None


def textx_nullable(expression: Any, seen: frozenset[int] = frozenset()) -> bool:
    if id(expression) in seen:
        return False
    seen = seen | {id(expression)}
    if isinstance(expression, arpeggio.Optional | arpeggio.ZeroOrMore | arpeggio.SyntaxPredicate):
        return True
    if isinstance(expression, arpeggio.OrderedChoice):  # a subclass of Sequence
        return any(textx_nullable(n, seen) for n in expression.nodes)
    if isinstance(expression, arpeggio.Sequence | arpeggio.UnorderedGroup):
        return all(textx_nullable(n, seen) for n in expression.nodes)
    if isinstance(expression, arpeggio.OneOrMore):
        return textx_nullable(expression.nodes[0], seen)
    return False


def textx_first_words(expression: Any, seen: frozenset[int] = frozenset()) -> set[str]:
    """The keywords textX's parser can match first for ``expression``."""
    if id(expression) in seen:
        return set()
    seen = seen | {id(expression)}
    keyword = textx_keyword(expression)
    if keyword is not None:
        return {keyword}
    if isinstance(expression, arpeggio.Sequence) and not isinstance(
        expression, arpeggio.OrderedChoice | arpeggio.UnorderedGroup
    ):
        found: set[str] = set()
        for node in expression.nodes:
            found |= textx_first_words(node, seen)
            if not textx_nullable(node):
                break
        return found
    if isinstance(expression, arpeggio.SyntaxPredicate):
        return set()
    return {w for n in getattr(expression, "nodes", []) for w in textx_first_words(n, seen)}


@pytest.mark.parametrize("language", sorted(LANGUAGES))
def test_the_keywords_are_those_textx_compiles(language: str) -> None:
    compiled: set[str] = set()
    stack, seen = list(textx_rules(language).values()), set()
    while stack:
        expression = stack.pop()
        if id(expression) not in seen:
            seen.add(id(expression))
            if (keyword := textx_keyword(expression)) is not None:
                compiled.add(keyword)
            stack.extend(getattr(expression, "nodes", []))
    assert grammar_keywords.keywords(language) == compiled


@pytest.mark.parametrize("language", sorted(LANGUAGES))
def test_each_rule_opens_with_the_words_textx_compiles(language: str) -> None:
    compiled = textx_rules(language)
    rules = grammar_keywords.rules(language)
    assert set(compiled) <= set(rules) | {"EOF", "Model", "STRING"}  # textX's own
    for name in sorted(set(compiled) & set(rules)):
        opening = {run[0] for run in grammar_keywords.heads(language, name)}
        assert opening == textx_first_words(compiled[name]), name


@pytest.mark.parametrize(
    ("language", "rule"),
    [("tsm", "Boolean"), ("fm", "BoolWord"), ("capability", "CapabilityBoolWord")],
)
def test_word_terminals_match_exactly_their_words(language: str, rule: str) -> None:
    (pattern,) = [
        e.to_match for e in [textx_rules(language)[rule]] if isinstance(e, arpeggio.RegExMatch)
    ]
    words = grammar_keywords.literal_words(language, rule)
    assert words == ("true", "false")
    for word in words:
        assert re.fullmatch(pattern, word)
    assert not re.match(pattern, "truely") and not re.match(pattern, "maybe")


@pytest.mark.parametrize(("language", "rule"), [("fm", "FeatureName"), ("fm", "CapabilityKey")])
def test_names_refuse_exactly_their_excluded_words(language: str, rule: str) -> None:
    pattern = textx_rules(language)[rule].to_match
    excluded = grammar_keywords.excluded_words(language, rule)
    for word in grammar_keywords.keywords(language) | {"feature", "capability", "has"}:
        assert (re.fullmatch(pattern, word) is None) == (word in excluded), word
    assert re.fullmatch(pattern, "andy") and re.fullmatch(pattern, "xor_2")


# -- the sets derived from the grammars ---------------------------------------------------
def test_the_language_server_s_sets_are_the_grammars() -> None:
    tsm_words, rm_words = grammar_keywords.keywords("tsm"), grammar_keywords.keywords("rm")
    statements, top = occurrences.TSM_STATEMENTS, set(completion.TSM_TOP)
    members, node = set(completion.TSM_MEMBERS), set(completion.TSM_NODE)
    assert statements >= {
        "container", "topic", "node", "param", "publishes", "subscribes", "provides", "calls",
        "bridge", "data", "transform", "store", "writer", "reader", "implementation", "endpoint",
    }  # fmt: skip
    # words that qualify the statement of the next word, or open none the walks read
    assert not statements & {"robot", "cloud", "optional", "system", "namespace"}
    assert tsm_words >= top | members | node >= statements
    assert top >= {"system", "robot", "cloud", "container", "bridge", "data", "transform"}
    assert members >= {"topic", "node", "optional", "store", "writer", "reader", "namespace"}
    assert members >= {"endpoint"} and node >= {"implementation", "param", "publishes", "calls"}
    assert not (top & node) and not (members & node)

    rm_statements = occurrences.RM_STATEMENTS
    assert rm_statements >= {"require", "implementation", "connect", "parameter", "migrate"}
    assert "when" in rm_statements and "bridge" not in rm_statements  # `connect bridge`
    assert completion.RM_TOP[0] == "when"
    assert completion.RM_TOP[1:] == ["resolution", "model", "tsm", "fm"]
    offered = [
        completion.AFTER_WHEN_FEATURE, completion.PARAMETER_VALUES,
        completion.AFTER_MIGRATE_NODE, completion.AFTER_CONNECT,
        completion.AFTER_CONNECT_INTERFACE, completion.AFTER_CONNECT_TO, completion.AFTER_NEW,
    ]  # fmt: skip
    assert rm_words >= rm_statements | {w for words in offered for w in words}
    assert set(completion.AFTER_WHEN_FEATURE) == {"selected", "not"}
    assert completion.PARAMETER_VALUES == ["feature", "true", "false"]
    assert completion.AFTER_MIGRATE_NODE == completion.AFTER_CONNECT_INTERFACE == ["to"]
    assert completion.AFTER_CONNECT == ["bridge"]
    assert completion.AFTER_BRIDGE_SOURCE == ["->"]
    assert completion.AFTER_CONNECT_TO == ["topic", "new", "server"]
    assert completion.AFTER_NEW == ["topic"]

    fm_words = grammar_keywords.keywords("fm")
    assert fm_words | {"true", "false"} == occurrences.FM_KEYWORDS
    operators = set(completion.FM_OPERATORS)
    assert fm_words >= operators >= {"and", "or", "not", "requires", "excludes"}


def test_the_vocabularies_of_the_builders_are_the_grammars() -> None:
    from spl.resolver.resolution import product_selection

    reserved = vocabulary.RESERVED_WORDS
    assert reserved >= {
        "abstract", "and", "attribute", "constraints", "excludes", "group", "mandatory",
        "not", "optional", "or", "requires", "sharing", "xor",
    }  # fmt: skip
    assert grammar_keywords.keywords("fm") >= reserved
    types, modes = vocabulary.ATTRIBUTE_TYPES, vocabulary.SHARING_MODES
    assert types[:4] == ("int", "double", "string", "bool")
    assert modes[:3] == ("public", "protected", "private")
    # the .tsm spells the same modes, and the resolver checks a selection's against them
    assert set(grammar_keywords.words_of("tsm", "SharingMode")) == set(vocabulary.SHARING_MODES)
    assert set(product_selection.SHARING_MODES) == set(vocabulary.SHARING_MODES)
    # attribute names the .fm writes with syntax of its own
    assert set(fm._RESERVED_ATTRIBUTES) <= grammar_keywords.keywords("fm")
    assert {"and", "or", "not", "true", "false"} <= transforms.RESERVED_FIELD_NAMES
    for word in grammar_keywords.words_of("tsm", "Expression"):
        assert word in transforms.RESERVED_FIELD_NAMES


def test_every_keyword_is_known_to_the_fast_reader_of_its_grammar() -> None:
    """A reader follows its grammar rule by rule, writing each keyword it matches: a
    keyword added to a .tx file and not to its reader fails here."""
    for language, files in READERS.items():
        source = "".join((DSL / f).read_text(encoding="utf-8") for f in files)
        written = set(re.findall(r'"([A-Za-z_][A-Za-z0-9_]*)"', source))
        if language == "tsm":  # the options closing an interface statement, read as declared
            written |= {
                keyword
                for entries in tsm_interface_reader.OPENED_BY.values()
                for *_, closing in entries
                for keyword, _, _ in closing
            }
        missing = grammar_keywords.keywords(language) - written
        assert not missing, f"{language}.tx keywords the reader never matches: {missing}"


def test_the_tsm_reader_dispatches_on_the_words_that_open_each_rule() -> None:
    def first(*rules: str) -> set[str]:
        return {run[0] for run in grammar_keywords.heads("tsm", *rules)}

    assert set(tsm_reader._ELEMENTS) == first("SystemElement")
    # `optional` is read before the member's own keyword, the last of its run
    assert set(tsm_reader._MEMBERS) == {run[-1] for run in grammar_keywords.heads("tsm", "Member")}
    assert set(tsm_reader._NODE_MEMBERS) == first("NodeMember")


# -- a keyword added to a grammar reaches every derived set --------------------------------
EDITS = {
    "tsm.tx": [
        ("Member: Topic | Node", "Member: Action | Topic | Node"),
        ("Topic: 'topic'", "Action: 'action' name=Name;\nTopic: 'topic'"),
        ("NodeMember: Parameter", "NodeMember: Remap | Parameter"),
        ("Parameter: 'param'", "Remap: 'remap' name=Name '->' to=Name;\nParameter: 'param'"),
        ("SystemElement: DataType", "SystemElement: Group | DataType"),
        ("DataType: 'data'", "Group: 'fleet' 'group' name=Name;\nDataType: 'data'"),
        ("('or' operands=AndExpr)*", "(('or' | 'xor') operands=AndExpr)*"),
    ],
    "rm.tx": [
        ("| ParameterStmt | MigrateStmt", "| ParameterStmt | MigrateStmt | RestartStmt"),
        ("MigrateStmt: 'migrate'", "RestartStmt: 'restart' node=QName;\nMigrateStmt: 'migrate'"),
        ("'migrate' node=QName 'to'", "'migrate' node=QName ('onto' | 'to')"),
    ],
    "fm.tx": [
        ("'public' | 'protected' | 'private'", "'public' | 'protected' | 'private' | 'fleet'"),
        ("'int' | 'double' | 'string' | 'bool'", "'int' | 'double' | 'string' | 'bool' | 'date'"),
        ("|requires|sharing|xor)", "|requires|sharing|xor|alt)"),
        ("'=>' | 'requires' | 'excludes'", "'=>' | 'requires' | 'excludes' | 'implies'"),
    ],
}
REPORT = """
import json, sys
from pathlib import Path
from spl.dsl import grammar_text
grammar_text.GRAMMARS = {n: Path(sys.argv[1]) / f"{n}.tx" for n in grammar_text.GRAMMARS}
from spl.dsl.fm import vocabulary as fm_vocabulary
from spl.dsl.tsm import transforms as tsm_transforms
from spl.lsp import completion, occurrences
print(json.dumps({
    "TSM_STATEMENTS": sorted(occurrences.TSM_STATEMENTS),
    "RM_STATEMENTS": sorted(occurrences.RM_STATEMENTS),
    "FM_KEYWORDS": sorted(occurrences.FM_KEYWORDS),
    "TSM_TOP": completion.TSM_TOP,
    "TSM_MEMBERS": completion.TSM_MEMBERS,
    "TSM_NODE": completion.TSM_NODE,
    "FM_OPERATORS": completion.FM_OPERATORS,
    "AFTER_MIGRATE_NODE": completion.AFTER_MIGRATE_NODE,
    "RESERVED_WORDS": sorted(fm_vocabulary.RESERVED_WORDS),
    "SHARING_MODES": fm_vocabulary.SHARING_MODES,
    "ATTRIBUTE_TYPES": fm_vocabulary.ATTRIBUTE_TYPES,
    "RESERVED_FIELD_NAMES": sorted(tsm_transforms.RESERVED_FIELD_NAMES),
}))
"""


def test_a_keyword_added_to_a_grammar_reaches_every_derived_set(tmp_path: Path) -> None:
    for grammar in DSL.glob("*/*.tx"):
        text = grammar.read_text(encoding="utf-8")
        for old, new in EDITS.get(grammar.name, []):
            assert text.count(old) == 1, old
            text = text.replace(old, new)
        (tmp_path / grammar.name).write_text(text, encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-c", REPORT, str(tmp_path)], capture_output=True, text=True, check=True
    )
    sets = json.loads(done.stdout)
    assert {"action", "remap"} <= set(sets["TSM_STATEMENTS"])
    assert "fleet" not in sets["TSM_STATEMENTS"] and "group" in sets["TSM_STATEMENTS"]
    assert {"fleet", "group"} <= set(sets["TSM_TOP"])
    assert "action" in sets["TSM_MEMBERS"] and "remap" in sets["TSM_NODE"]
    assert "restart" in sets["RM_STATEMENTS"]
    assert set(sets["AFTER_MIGRATE_NODE"]) == {"onto", "to"}
    assert {"fleet", "date", "implies"} <= set(sets["FM_KEYWORDS"])
    assert "implies" in sets["FM_OPERATORS"]
    assert "alt" in sets["RESERVED_WORDS"]
    assert sets["SHARING_MODES"][-1] == "fleet" and sets["ATTRIBUTE_TYPES"][-1] == "date"
    assert "xor" in sets["RESERVED_FIELD_NAMES"]


def test_reading_the_grammars_is_cheap() -> None:
    """Every ``spl check`` and the language server derive their sets at import: the
    grammars are read by a small parser, never by building textX's metamodels."""
    done = subprocess.run(
        [
            sys.executable,
            "-c",
            "import sys, spl.dsl.fm.vocabulary, spl.dsl.tsm.transforms, spl.lsp.completion;"
            "print(sorted(m for m in sys.modules if m.startswith(('textx', 'arpeggio'))))",
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    assert done.stdout.strip() == "[]"
