"""Every .tsm, .fm and .rm example of the documentation parses with spl's own parsers.

An example is a fenced block whose info string is the language: ```tsm, ```fm or ```rm,
at the start of a line in a page of docs/. It must be a whole file of that language. A
.rm names its .tsm and .fm (``tsm "..."``, ``fm "..."``), found in one of two ways,
said by an HTML comment on the line right before the fence:

- ``<!-- against: product_lines/mapping3d -->``: the files of that shipped line;
- otherwise the page's own examples: a ```tsm or ```fm block right after
  ``<!-- file: farm.tsm -->`` is written under that name into a folder of the page,
  where the page's .rm examples are parsed.

A block whose info string merely resembles a language (```.tsm, ```TSM, ```rm text) is
an example that would go unchecked: it fails here too.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.fm import language as fm
from spl.dsl.rm import language as rm
from spl.dsl.tsm import language as tsm

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
LANGUAGES = ("tsm", "fm", "rm")

BLOCK = re.compile(
    r"^(?:<!-- (?P<marker>file|against): (?P<argument>\S+) -->\n)?"
    r"```(?P<info>[^\n`]*)\n(?P<code>.*?)^```[ \t]*$",
    re.M | re.S,
)
# the other info strings the pages use: anything else is a typo or an unchecked example
OTHER_INFO = {"", "sh", "yaml", "lua", "json", "xml", "text", "mermaid"}


@dataclass(frozen=True)
class Example:
    page: str
    line: int
    language: str
    code: str
    marker: str | None
    argument: str | None

    @property
    def id(self) -> str:
        return f"{self.page}:{self.line}"


def examples_of(page: Path) -> tuple[list[Example], list[str]]:
    """The page's language examples, and the info strings it should not use."""
    text = page.read_text(encoding="utf-8")
    found, odd = [], []
    for match in BLOCK.finditer(text):
        info = match["info"].strip()
        line = text.count("\n", 0, match.start("info")) + 1
        if info in LANGUAGES:
            found.append(
                Example(page.name, line, info, match["code"], match["marker"], match["argument"])
            )
        elif info not in OTHER_INFO:
            odd.append(f"{page.name}:{line}: ```{info}")
    return found, odd


PAGES = sorted(DOCS.glob("*.md"))
EXAMPLES = [example for page in PAGES for example in examples_of(page)[0]]


def write_page_files(examples: list[Example], folder: Path) -> None:
    """The page's ``<!-- file: NAME -->`` examples, written as the files a .rm names."""
    for example in examples:
        if example.marker == "file":
            assert Path(example.argument).suffix == f".{example.language}", example.id
            (folder / example.argument).write_text(example.code, encoding="utf-8")


def parse_example(example: Example, folder: Path) -> None:
    """Parse one example as spl reads a file of its language (ModelError when broken)."""
    filename = f"docs/{example.page}, example at line {example.line}"
    if example.language == "tsm":
        tsm.parse_text(example.code, filename)
    elif example.language == "fm":
        fm.parse_text(example.code, filename)
    else:
        if example.marker == "against":
            base = ROOT / example.argument
            assert base.is_dir(), f"{example.id}: no product line {example.argument}"
        else:
            base = folder
            page = [e for e in EXAMPLES if e.page == example.page]
            write_page_files(page, folder)
        rm.parse_text(example.code, filename, base=base)


@pytest.mark.parametrize("example", EXAMPLES, ids=[e.id for e in EXAMPLES])
def test_example_parses(example: Example, tmp_path: Path) -> None:
    try:
        parse_example(example, tmp_path)
    except ModelError as error:
        pytest.fail(f"docs/{example.id}: the {example.language} example does not parse:\n{error}")


def test_every_language_has_checked_examples() -> None:
    for language in LANGUAGES:
        pages = {e.page for e in EXAMPLES if e.language == language}
        assert f"{language}.md" in pages, f"docs/{language}.md has no ```{language} example"
    assert sum(e.language == "rm" and e.marker != "against" for e in EXAMPLES) >= 1
    assert sum(e.marker == "against" for e in EXAMPLES) >= 1


def test_no_example_hides_behind_another_info_string() -> None:
    odd = [o for page in PAGES for o in examples_of(page)[1]]
    assert not odd, "fenced blocks with an unknown info string (a typo?):\n" + "\n".join(odd)


BROKEN = {
    "tsm": "system S\nrobot container R {\n    node N { subscribes s <- Missing }\n}\n",
    "fm": "feature model F\nroot R {\n    optional A\n}\nconstraints {\n    A requires B\n}\n",
    "rm": (
        'resolution model M\ntsm "mapping.tsm"\nfm  "mapping.fm"\n'
        "when Stereo selected {\n    migrate MapOptimiser to Robot\n}\n"
    ),
}


@pytest.mark.parametrize("language", LANGUAGES)
def test_a_broken_example_fails(language: str, tmp_path: Path) -> None:
    """The check is real: an example naming something that does not exist is refused."""
    page = f"```{language}\n{BROKEN[language]}```\n"
    if language == "rm":
        page = "<!-- against: product_lines/mapping3d -->\n" + page
    (tmp_path / f"{language}.md").write_text(page, encoding="utf-8")
    (example,) = examples_of(tmp_path / f"{language}.md")[0]
    with pytest.raises(ModelError):
        parse_example(example, tmp_path)
