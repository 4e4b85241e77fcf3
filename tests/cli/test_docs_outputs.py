"""What a page of docs/ shows spl printing or writing for its own example line is what spl
prints or writes.

A fenced block right after ``<!-- output: spl ARGS -->`` is output of that command, run on
the page's line: the folder its ``<!-- file: NAME -->`` examples are written to
(tests/cli/test_docs_examples.py parses those), named ``LINE`` in ARGS; ``OUT`` names a
bundle folder. ``<!-- output: PATH of spl ARGS -->`` shows part of the file PATH of the
bundle the command writes. The block's lines, stripped, must be a run of consecutive
lines of the command's stdout, its stderr or the file, with the line's folder left out
of the paths it prints.
"""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass
from pathlib import Path

import pytest

from support.cli_outcome import run

DOCS = Path(__file__).resolve().parents[2] / "docs"
FILE = re.compile(r"^<!-- file: (?P<name>\S+) -->\n```\w*\n(?P<code>.*?)^```", re.M | re.S)
OUTPUT = re.compile(
    r"^<!-- output: (?:(?P<path>\S+) of )?spl (?P<args>[^>]*?) -->\n```\w*\n(?P<shown>.*?)^```",
    re.M | re.S,
)


@dataclass(frozen=True)
class Shown:
    page: str
    line: int
    path: str | None
    args: str
    text: str

    @property
    def id(self) -> str:
        return f"{self.page}:{self.line}"


def shown_outputs() -> list[Shown]:
    found = []
    for page in sorted(DOCS.glob("*.md")):
        text = page.read_text(encoding="utf-8")
        for match in OUTPUT.finditer(text):
            line = text.count("\n", 0, match.start()) + 1
            found.append(Shown(page.name, line, match["path"], match["args"], match["shown"]))
    return found


SHOWN = shown_outputs()


def lines(text: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if line.strip()]


def is_run_of(part: list[str], whole: list[str]) -> bool:
    return any(whole[i : i + len(part)] == part for i in range(len(whole) - len(part) + 1))


def test_pages_show_outputs() -> None:
    assert {s.page for s in SHOWN} >= {"semantics.md", "deployment.md"}


@pytest.mark.parametrize("shown", SHOWN, ids=[s.id for s in SHOWN])
def test_a_shown_output_is_what_spl_gives(shown: Shown, tmp_path: Path) -> None:
    line = tmp_path / "line"
    line.mkdir()
    page = (DOCS / shown.page).read_text(encoding="utf-8")
    for match in FILE.finditer(page):
        (line / match["name"]).write_text(match["code"], encoding="utf-8")
    out = tmp_path / "out"
    args = [
        {"LINE": str(line), "OUT": str(out)}.get(word, word) for word in shlex.split(shown.args)
    ]
    result = run(*args)
    assert result.exit_code == 0, f"docs/{shown.id}: spl {shown.args}\n{result.stderr}"
    if shown.path is not None:
        texts = [(out / shown.path).read_text(encoding="utf-8")]
    else:
        texts = [result.stdout, result.stderr]
    wanted = lines(shown.text)
    assert wanted, f"docs/{shown.id}: an empty output block"
    printed = [lines(text.replace(f"{line}/", "")) for text in texts]
    assert any(is_run_of(wanted, whole) for whole in printed), (
        f"docs/{shown.id}: spl {shown.args} gives\n" + "\n---\n".join("\n".join(p) for p in printed)
    )
