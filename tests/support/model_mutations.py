"""Random mutations of model text, for the fuzz tests.

A mutation works on tokens (identifiers, numbers, strings, punctuation, white space)
or on lines, so most mutants are near-misses of real models: a name replaced by a
keyword of another language, a brace deleted, a statement duplicated, a file cut off
in the middle. Positions are drawn as large integers and taken modulo the length, so
hypothesis shrinks them towards the start of the text.
"""

from __future__ import annotations

import re
from functools import cache
from pathlib import Path

from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[2]
GRAMMARS = ROOT / "src" / "spl" / "dsl"

TOKEN = re.compile(r'[A-Za-z_]\w*|\d+(?:\.\d+)?|"(?:\\.|[^"\\\n])*"|\s+|.', re.S)
IDENT = re.compile(r"[A-Za-z_]\w*")
NUMBER = re.compile(r"\d+(?:\.\d+)?")

# Names no model may carry into a generated file, and names that are merely unusual.
ODD_NAMES = (
    "é",
    "Ωmega",
    "x\u200by",
    "名前",
    "\U0001f916",
    "Robot\u0301",
    "_",
    "__init__",
    "0abc",
    "a.b",
    "a-b",
    "$(eval 1)",
    "<x/>",
    "&amp;",
    "'",
    '"',
    "\\",
    "\t",
    "\r\n",
    "\x00",
    "\ufeff",
    "\x7f",
    "None",
    "null",
    "-1",
    "1e999",
    "99999999999999999999999",
    "nan",
    "inf",
    "/",
    "//",
    "/*",
    "\udcff",  # written with surrogateescape: a byte that is not UTF-8
)
ODD_NUMBERS = ("0", "-0", "-1", "0.0", "1e999", "4294967296", "9" * 25, "9" * 5000, ".5", "1.")
PUNCTUATION = (*"{}()[]<>-.:,;=\"'/\\*+!?#@%&|~^`", "->", "<-", "..", "=>", "<=>")


@cache
def keywords() -> tuple[str, ...]:
    """Every keyword of the three grammars (the quoted words of the .tx files)."""
    found: set[str] = set()
    for grammar in sorted(GRAMMARS.glob("*/*.tx")):
        found.update(re.findall(r"'([A-Za-z_]+)'", grammar.read_text(encoding="utf-8")))
    return tuple(sorted(found))


def long_names() -> st.SearchStrategy[str]:
    return st.sampled_from(("N" * 300, "a" * 5000, "x" * 70000, "_" + "9" * 400))


def replacements(text: str) -> st.SearchStrategy[str]:
    """What an identifier may be replaced with: another name of the same file, a
    keyword, an odd name, a very long one, or arbitrary text."""
    names = sorted(set(IDENT.findall(text))) or ["x"]
    return st.one_of(
        st.sampled_from(names),
        st.sampled_from(keywords()),
        st.sampled_from(ODD_NAMES),
        long_names(),
        st.text(max_size=12),
    )


POSITION = st.integers(min_value=0, max_value=10**6)


def mutation(text: str) -> st.SearchStrategy[tuple]:
    inserted = st.one_of(
        st.sampled_from(PUNCTUATION), st.sampled_from(keywords()), st.sampled_from(ODD_NAMES)
    )
    return st.one_of(
        st.tuples(st.just("delete_token"), POSITION),
        st.tuples(st.just("duplicate_token"), POSITION),
        st.tuples(st.just("swap_tokens"), POSITION, POSITION),
        st.tuples(st.just("replace_name"), POSITION, replacements(text)),
        st.tuples(
            st.just("replace_name"),
            POSITION,
            st.sampled_from(sorted(set(IDENT.findall(text))) or ["x"]),
        ),
        st.tuples(st.just("replace_number"), POSITION, st.sampled_from(ODD_NUMBERS)),
        st.tuples(st.just("insert"), POSITION, inserted),
        st.tuples(st.just("delete_line"), POSITION),
        st.tuples(st.just("duplicate_line"), POSITION),
        st.tuples(st.just("swap_lines"), POSITION, POSITION),
        st.tuples(st.just("truncate"), POSITION),
    )


def mutations(text: str, most: int = 4) -> st.SearchStrategy[list[tuple]]:
    return st.lists(mutation(text), min_size=1, max_size=most)


def mutate(text: str, operations: list[tuple]) -> str:
    """``text`` with the ``operations`` applied in order."""
    for operation in operations:
        text = _apply(text, operation)
    return text


def _apply(text: str, operation: tuple) -> str:
    kind, *args = operation
    if kind.endswith("_line") or kind == "swap_lines":
        lines = text.splitlines(keepends=True) or [""]
        i = args[0] % len(lines)
        if kind == "delete_line":
            del lines[i]
        elif kind == "duplicate_line":
            lines.insert(i, lines[i])
        else:
            j = args[1] % len(lines)
            lines[i], lines[j] = lines[j], lines[i]
        return "".join(lines)
    if kind == "truncate":
        return text[: args[0] % (len(text) + 1)]
    tokens = TOKEN.findall(text) or [""]
    i = args[0] % len(tokens)
    if kind == "delete_token":
        del tokens[i]
    elif kind == "duplicate_token":
        tokens.insert(i, tokens[i])
    elif kind == "swap_tokens":
        j = args[1] % len(tokens)
        tokens[i], tokens[j] = tokens[j], tokens[i]
    elif kind in ("replace_name", "replace_number"):
        pattern = IDENT if kind == "replace_name" else NUMBER
        found = [k for k, token in enumerate(tokens) if pattern.fullmatch(token)] or [i]
        tokens[found[args[0] % len(found)]] = args[1]
    else:  # insert, with a space on each side half of the time
        tokens.insert(i, args[1] if i % 2 else f" {args[1]} ")
    return "".join(tokens)
