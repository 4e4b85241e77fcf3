"""The VS Code extension in editors/vscode: it starts ``spl lsp`` for the files the
server serves, and its TextMate grammars know every keyword of the textX grammars."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from spl.lsp.checking import SUFFIXES

ROOT = Path(__file__).resolve().parents[1]
EXTENSION = ROOT / "editors" / "vscode"
GRAMMARS = {"tsm": ["tsm.tx"], "fm": ["fm.tx", "capability.tx"], "rm": ["rm.tx"]}


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
    package = manifest()
    (entry,) = [g for g in package["contributes"]["grammars"] if g["language"] == f"spl-{language}"]
    grammar = json.loads((EXTENSION / entry["path"]).read_text(encoding="utf-8"))
    assert grammar["scopeName"] == entry["scopeName"]
    keywords = set()
    for file in GRAMMARS[language]:
        text = (ROOT / "dsl" / file).read_text(encoding="utf-8")
        keywords |= set(re.findall(r"'([a-z_]+)'", text))
    match = grammar["repository"]["keywords"]["match"]
    highlighted = set(re.fullmatch(r"\\b\((.*)\)\\b", match).group(1).split("|"))
    assert highlighted == keywords - {"true", "false"}
    for rule in grammar["repository"].values():
        for item in rule.get("patterns", [rule]):
            for key in ("match", "begin", "end"):
                if key in item:
                    re.compile(item[key])  # the patterns are plain regular expressions


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_extension_script_is_valid_javascript():
    subprocess.run(["node", "--check", str(EXTENSION / "extension.js")], check=True)
