"""spl's UVL reader accepts and refuses the same files as the reference grammar.

The reference is uvlparser (PyPI), the ANTLR grammar of the UVL project run by the
antlr4 Python runtime. Every syntax error the grammar reports counts as a refusal here
(uvlparser's own ``get_tree`` driver prints errors that mention a tab character as
warnings and goes on; the grammar itself refuses those files).

The files: the vendored community models (tests/data/feature-models, accepted by both)
and small hand-written ones in tests/models/uvl_conformance, named by what is expected:

- ``ok_*``: valid UVL spl reads, every language level (:func:`read_uvl_plain`, what
  analysis reads) — both accept;
- ``bad_*``: not UVL — both refuse;
- ``unsupported_*``: valid UVL spl cannot represent (a model without a features
  section) — the grammar accepts, spl refuses with "... not supported";
- ``semantic_*``: valid syntax with an error the grammar does not look for (an unknown
  or duplicate feature, an empty cardinality) — the grammar accepts, spl refuses.
"""

from __future__ import annotations

import random
from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.interop.uvl import read_uvl_plain
from spl.dsl.interop.uvl_reader import parse_uvl_plain

from support.real_models import REAL_MODELS

HERE = Path(__file__).parents[1] / "models" / "uvl_conformance"
CASES = sorted(HERE.glob("*.uvl")) + sorted(REAL_MODELS.glob("*.uvl"))


class _Refused(Exception):
    pass


def reference_accepts(path: Path) -> bool:
    return reference_accepts_text(path.read_text(encoding="utf-8"))


def reference_accepts_text(text: str) -> bool:
    from antlr4 import CommonTokenStream, InputStream
    from antlr4.error.ErrorListener import ErrorListener
    from uvl.UVLCustomLexer import UVLCustomLexer
    from uvl.UVLPythonParser import UVLPythonParser

    class Refuse(ErrorListener):
        def syntaxError(self, recognizer, offendingSymbol, line, column, msg, e):
            raise _Refused(f"{line}:{column} {msg}")

    lexer = UVLCustomLexer(InputStream(text))
    lexer.removeErrorListeners()
    lexer.addErrorListener(Refuse())
    parser = UVLPythonParser(CommonTokenStream(lexer))
    parser.removeErrorListeners()
    parser.addErrorListener(Refuse())
    try:
        parser.featureModel()
    except _Refused:
        return False
    return True


def category(path: Path) -> str:
    return path.name.split("_", 1)[0] if path.parent == HERE else "ok"


def test_every_category_has_cases() -> None:
    found = {category(path) for path in CASES}
    assert found == {"ok", "bad", "unsupported", "semantic"}
    assert sum(category(path) == "bad" for path in CASES) >= 20


@pytest.mark.parametrize("path", CASES, ids=[p.name for p in CASES])
def test_same_verdict_as_the_reference_grammar(path: Path) -> None:
    reference = reference_accepts(path)
    try:
        read_uvl_plain(path)
        messages: list[str] = []
    except ModelError as exc:
        messages = [str(d) for d in exc.diagnostics]
        # every refusal is located in the file read
        assert all(m.startswith(f"{path}:") for m in messages), messages
    kind = category(path)
    if kind == "ok":
        assert reference and not messages, messages
    elif kind == "bad":
        assert not reference and messages
    elif kind == "unsupported":
        assert reference and messages
        assert any("not supported" in m for m in messages), messages
    else:
        assert reference and messages
        assert not any("not supported" in m for m in messages), messages


# what a mutation inserts: tokens, keywords, brackets, comment marks, line breaks, indents
PIECES = (
    *("\n", "\t", " ", "\n\t", "\n\t\t", "\n\n", "(", ")", "{", "}", "[", "]", "[1..2]"),
    *("|", "&", "!", "=>", "<=>", '"', "'", ",", ".", "//", "/*", "*/", "A", "1", "1.5"),
    *("optional", "mandatory", "or", "alternative", "features", "constraints", "namespace"),
    *("abstract", "true", "Integer", "cardinality"),
)
SEMANTIC = (
    *("unknown feature", "duplicate feature", "bad cardinality", "sharing must", "attribute"),
    "abstract takes",
    *("imported model", "import cycle", "only the root feature"),  # composition
    "no feature has",  # an aggregate of an attribute no feature declares (Arithmetic level)
)


def mutants(count: int, seed: int) -> list[str]:
    """Small valid files with one to three random edits (insert, delete, repeat a line)."""
    rng = random.Random(seed)
    seeds = [p.read_text(encoding="utf-8") for p in sorted(HERE.glob("ok_*.uvl"))]
    found = []
    for _ in range(count):
        text = rng.choice(seeds)
        for _ in range(rng.randint(1, 3)):
            at, edit = rng.randrange(len(text) + 1), rng.random()
            if edit < 0.4:
                text = text[:at] + rng.choice(PIECES) + text[at:]
            elif edit < 0.8:
                text = text[:at] + text[at + rng.randint(1, 3) :]
            else:
                lines = text.split("\n")
                line = rng.randrange(len(lines))
                text = "\n".join([*lines[: line + 1], *lines[line:]])
        found.append(text)
    return found


def test_mutated_files_get_the_same_verdict() -> None:
    """Random edits of the valid files (fixed seed): never accepted by one reader only,
    except where spl refuses valid UVL it cannot represent or that names no feature."""
    differences = []
    for text in mutants(300, seed=17):
        reference = reference_accepts_text(text)
        try:
            parse_uvl_plain(text, "mutant.uvl")
            messages: list[str] = []
        except ModelError as exc:
            messages = [d.message for d in exc.diagnostics]
        explained = all("not supported" in m or m.startswith(SEMANTIC) for m in messages)
        if not messages and not reference:
            differences.append(("spl accepts, the grammar refuses", text))
        elif messages and reference and not explained:
            differences.append((f"only spl refuses: {messages}", text))
    assert differences == []
