"""The code cites no document outside the repository: sections of a specification
(``SPEC 5.2``), issue numbers (``issue 17``) and the seed papers as files (``seeds/003``,
``../shared/...``) are not there for a reader of the repository. The code cites its own
manual instead (``docs/resolution.md``, step 3) and a paper by the title docs/index.md
gives it.

Checked: the Python modules, grammars (.tx) and metamodels (.ecore) of the package
folders, the benchmarks and scripts, and the templates of the generators: what
they write is read by the users of a bundle, who have the repository even less."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FOLDERS = ("src", "bench", "scripts")
SUFFIXES = (".py", ".tx", ".ecore", ".j2")
CITATION = re.compile(
    r"\bSPEC\b"  # SPEC 5.2, (SPEC section 8)
    r"|\b[Ii]ssue #?\d+"  # issue 17
    r"|\bseeds/"  # seeds/003, seeds/000 Fig. 4
    r"|\.\./shared/"  # ../shared/...
)


def checked_files() -> list[Path]:
    return sorted(
        path
        for folder in FOLDERS
        for path in (ROOT / folder).rglob("*")
        if path.suffix in SUFFIXES and path.is_file() and "__pycache__" not in path.parts
    )


def citations(text: str) -> list[tuple[int, str]]:
    return [
        (number, line.strip())
        for number, line in enumerate(text.splitlines(), start=1)
        if CITATION.search(line)
    ]


def test_the_checked_folders_hold_code() -> None:
    files = checked_files()
    assert len(files) > 150
    assert ROOT / "src" / "spl" / "metamodels" / "tsm.ecore" in files
    assert ROOT / "src" / "spl" / "dsl" / "fm" / "fm.tx" in files


@pytest.mark.parametrize(
    "text",
    [
        "(SPEC 5.2)",
        "SPEC section 8, the checks",
        "the 0.3 s target of issue 17",
        "(Issue 4 benchmark)",
        "the notation of seeds/003 Fig. 4",
        "see ../shared/notes.md",
    ],
)
def test_a_citation_is_found(text: str) -> None:
    assert citations(f"x = 1\n# {text}\n") == [(2, f"# {text}")]


@pytest.mark.parametrize(
    "text",
    [
        "_SPECIAL = re.compile('[$]')",  # a name containing SPEC
        'f"shared/ros1/{tag}.launch"',  # a fleet bundle's folder
        "docs/resolution.md, step 3",
        "the mapping paper (docs/index.md)",
    ],
)
def test_what_is_no_citation(text: str) -> None:
    assert citations(text) == []


def test_no_code_cites_a_document_outside_the_repository() -> None:
    found = [
        f"{path.relative_to(ROOT)}:{number}: {line}"
        for path in checked_files()
        for number, line in citations(path.read_text(encoding="utf-8"))
    ]
    assert not found, "cite docs/*.md (or a paper by its title) instead:\n" + "\n".join(found)
