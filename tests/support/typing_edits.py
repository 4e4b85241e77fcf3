"""Edits of a model text as a typing user makes them, and worse: for the tests of what
the editor keeps from one reading or check to the next."""

from __future__ import annotations

import random
import re


def edits_of(text: str, rng: random.Random, count: int) -> list[str]:
    """``count`` texts, each ``text`` with a stretch of it deleted, doubled or replaced
    by a piece of another place (the edits of a typing user, and worse)."""
    found = []
    for _ in range(count):
        start = rng.randrange(len(text) + 1)
        end = min(len(text), start + rng.choice((0, 1, 2, 5, 20, 200)))
        other = rng.randrange(len(text) + 1)
        piece = rng.choice(("", text[start:end], text[other : other + 30], "x", " }", "\n"))
        found.append(text[:start] + piece + text[end:])
        if rng.random() < 0.3:
            text = found[-1]  # sometimes the edits pile up
    return found


def line_starts(text: str) -> list[int]:
    return [0, *(i + 1 for i, c in enumerate(text) if c == "\n" and i + 1 < len(text))]


def model_edit(path: str, text: str, names: dict[str, list[str]], rng: random.Random) -> str:
    """One edit of a line's .tsm or .rm (``path``), most often one that keeps it valid:
    a comment line moving what follows, a value changed in place, an optional node added
    to a container, an element added or removed; or a typing edit that breaks it.
    ``names`` holds the line's ``features`` and ``nodes``."""
    choice = rng.random()
    if choice < 0.2:
        return rng.choice(edits_of(text, rng, 3))
    if choice < 0.4:
        at = rng.choice(line_starts(text))
        return text[:at] + "// a note\n" + text[at:]
    if path.endswith(".tsm"):
        if choice < 0.7:
            values = list(re.finditer(r"implementation (\S+)", text))
            if values:
                value = rng.choice(values)
                return text[: value.end()] + "_2" + text[value.end() :]
        ends = [m.start() + 1 for m in re.finditer(r"\n}\n", text)]
        at = rng.choice(ends) if ends else len(text)
        added = f"    optional node Added{rng.randrange(99)} {{\n"
        added += "        implementation a/n\n    }\n"
        return text[:at] + added + text[at:]
    elements = list(re.finditer(r"when [^{]*\{[^}]*\}\n?", text))
    if choice < 0.7 and elements:
        gone = rng.choice(elements)
        return text[: gone.start()] + text[gone.end() :]
    feature, node = rng.choice(names["features"]), rng.choice(names["nodes"])
    return text + f"\nwhen {feature} selected {{\n    implementation {node} = x/y\n}}\n"
