"""The VS Code extension in editors/vscode: it starts ``spl lsp`` for the files the
server serves, and its TextMate grammars know every keyword of the textX grammars (the
keywords, literals and declaring keywords, compared with ``spl.dsl.grammar_keywords``)."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from spl.dsl import grammar_keywords
from spl.dsl.tsm.options import INTERFACE_OPTIONS
from spl.lsp.checking import SUFFIXES
from spl.metamodels.interface_kinds import KINDS

ROOT = Path(__file__).resolve().parents[2]
EXTENSION = ROOT / "editors" / "vscode"
GRAMMARS = {"tsm": ["tsm/tsm.tx"], "fm": ["fm/fm.tx", "fm/capability.tx"], "rm": ["rm/rm.tx"]}


def manifest() -> dict:
    return json.loads((EXTENSION / "package.json").read_text(encoding="utf-8"))


def test_extension_starts_spl_lsp_for_every_suffix_the_server_checks():
    package = manifest()
    command = package["contributes"]["configuration"]["properties"]["spl.command"]["default"]
    assert command == ["spl", "lsp"]
    suffixes = {e for lang in package["contributes"]["languages"] for e in lang["extensions"]}
    assert suffixes | {".xml"} == set(SUFFIXES)  # .xml is VS Code's own language
    script = (EXTENSION / "extension.js").read_text(encoding="utf-8")
    selected = set(re.findall(r'language: "([\w-]+)"', script))
    assert selected == {lang["id"] for lang in package["contributes"]["languages"]} | {"xml"}
    assert package["main"] == "./extension.js"


@pytest.mark.parametrize("language", sorted(GRAMMARS))
def test_textmate_grammar_highlights_every_keyword_of_the_language(language: str):
    """The keywords, the literals and the declaring keywords of each TextMate grammar
    are those of its textX grammars (read by ``spl.dsl.grammar_keywords``, as the
    language server's sets are): a keyword added to a .tx file fails here until the
    TextMate grammar highlights it."""
    package = manifest()
    (entry,) = [g for g in package["contributes"]["grammars"] if g["language"] == f"spl-{language}"]
    grammar = json.loads((EXTENSION / entry["path"]).read_text(encoding="utf-8"))
    assert grammar["scopeName"] == entry["scopeName"]
    keywords = grammar_keywords.keywords(language)
    assert keywords == {
        word
        for file in GRAMMARS[language]
        for word in _string_words(ROOT / "src" / "spl" / "dsl" / file)
    }
    constants = set(_words(grammar["repository"]["constants"]["match"]))
    assert constants == set(BOOLEANS[language]())
    # the words after an interface statement's first (``provides action``) are
    # highlighted by their place, as the declarations' second capture
    qualifiers = QUALIFIERS if language == "tsm" else set()
    highlighted = set(_words(grammar["repository"]["keywords"]["match"]))
    # an interface statement's option keyword (``timeout 2.5``) may be highlighted by its
    # place alone, as the options pattern does (the next test)
    by_place = OPTION_KEYWORDS if language == "tsm" else set()
    assert highlighted <= keywords - constants - qualifiers
    assert keywords - constants - qualifiers - highlighted <= by_place
    declaring = set(_words(grammar["repository"]["declarations"]["match"]))
    assert declaring <= keywords
    assert _declaring_keywords(language) - qualifiers <= declaring
    for rule in grammar["repository"].values():
        for item in rule.get("patterns", [rule]):
            for key in ("match", "begin", "end"):
                if key in item:
                    re.compile(item[key])  # the patterns are plain regular expressions


# the words of the interface kinds' keywords after their first (``action``)
QUALIFIERS = {word for kind in KINDS for word in kind.keyword.split()[1:]}


def test_textmate_grammar_highlights_an_interface_statement_by_its_place():
    """Every interface kind's statement, and one of a kind not yet in the registry, is
    highlighted whole: its keyword's words as keywords and the interface's name as a
    declared name, so that a kind added to the registry needs no edit of the grammar."""
    (entry,) = [g for g in manifest()["contributes"]["grammars"] if g["language"] == "spl-tsm"]
    grammar = json.loads((EXTENSION / entry["path"]).read_text(encoding="utf-8"))
    declarations = re.compile(grammar["repository"]["declarations"]["match"])
    keywords = re.compile(grammar["repository"]["keywords"]["match"])
    statements = [(k.keyword, f"{k.keyword} x : p/T") for k in KINDS]
    statements += [(k.keyword, f"{k.keyword} x {k.arrow} N.s") for k in KINDS if k.arrow]
    statements.append(("calls reconfigure", "calls reconfigure x -> N.s"))
    for keyword, statement in statements:
        found = declarations.match(statement)
        assert found is not None, statement
        first, qualifier, name = found.groups()
        assert (first, qualifier or None, name) == (*_split(keyword), "x"), statement
        assert keywords.match(first)
    # a service named like a qualifier is a name: ``provides action : p/T``
    assert declarations.match("provides action : p/T").groups() == ("provides", None, "action")
    assert declarations.match("topic Scan : p/T").groups() == ("topic", None, "Scan")


# the keywords of the options closing an interface statement (tsm.tx)
OPTION_KEYWORDS = {o.keyword for found in INTERFACE_OPTIONS.values() for o in found}


def test_textmate_grammar_highlights_a_statement_option_by_its_place():
    """The keyword of an option, a word right before its string or number, is highlighted
    whatever the word, so that an option added to tsm.tx (``timeout 2.5``) needs no edit
    of the grammar; a name or an expression's operand before a number is not."""
    (entry,) = [g for g in manifest()["contributes"]["grammars"] if g["language"] == "spl-tsm"]
    grammar = json.loads((EXTENSION / entry["path"]).read_text(encoding="utf-8"))
    options = re.compile(grammar["repository"]["options"]["match"])
    assert {"name", "external"} <= OPTION_KEYWORDS
    lines = {
        'provides s : p/T name "/s"': "name",
        'calls c -> N.s external "a driver"': "external",
        "calls c -> N.s timeout 2.5": "timeout",
        "calls c -> N.s retries\t3": "retries",
        "calls c -> N.s every .5": "every",
    }
    for line, keyword in lines.items():
        found = [m.group() for m in options.finditer(line)]
        assert found == [keyword], line
    for line in ("topic Scan : p/T", "x = a - 3", "param p : int = 3", "x = f(a, 3)"):
        assert options.search(line) is None, line


def _split(keyword: str) -> tuple[str, str | None]:
    first, *rest = keyword.split()
    return first, " ".join(rest) or None


BOOLEANS = {
    "tsm": lambda: grammar_keywords.literal_words("tsm", "Boolean"),
    "fm": lambda: grammar_keywords.literal_words("fm", "BoolWord"),
    "rm": lambda: grammar_keywords.words_of("rm", "Boolean"),
}


def _string_words(path: Path) -> set[str]:
    """The quoted words of a grammar file, read plainly (a second reading)."""
    return set(re.findall(r"'([a-z_]+)'", path.read_text(encoding="utf-8")))


def _words(pattern: str) -> list[str]:
    """The words of a TextMate pattern ``\\b(a|b|c)\\b...``."""
    return re.match(r"\\b\(([a-z_|]+)\)", pattern).group(1).split("|")


def _declaring_keywords(language: str) -> set[str]:
    """The keywords written right before a declared ``name=`` in the grammar."""
    found: set[str] = set()

    def keyword(expr: tuple) -> str | None:
        if expr[0] == "rep":
            return keyword(expr[2])
        if expr[0] == "assign" and expr[2] == "?=":
            return keyword(expr[3])
        return expr[1] if expr[0] == "str" and grammar_keywords.is_word(expr[1]) else None

    def declares(expr: tuple) -> bool:
        inner = expr[2] if expr[0] == "rep" else expr
        return inner[0] == "assign" and inner[1] == "name"

    def walk(expr: tuple) -> None:
        if expr[0] in ("seq", "choice"):
            if expr[0] == "seq":
                for before, after in zip(expr[1], expr[1][1:], strict=False):
                    if declares(after) and (word := keyword(before)) is not None:
                        found.add(word)
            for part in expr[1]:
                walk(part)
        elif expr[0] in ("rep", "assign", "pred"):
            walk(expr[-1])

    for body in grammar_keywords.rules(language).values():
        walk(body)
    return found


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_extension_script_is_valid_javascript():
    subprocess.run(["node", "--check", str(EXTENSION / "extension.js")], check=True)
