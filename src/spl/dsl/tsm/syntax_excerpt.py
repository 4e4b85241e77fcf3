"""The excerpt of a .tsm text textX needs to word its syntax error.

The fast reader (:mod:`spl.dsl.tsm.reader`) leaves a text it cannot read to textX, so
that syntax errors keep textX's wording; textX reading a whole 10,000-node file takes
seconds to tens of seconds. Where the reader gave up tells which declarations textX
need not read again (``tests/test_tsm_reader.py`` compares the wording from the excerpt
with the whole file's).
"""

from __future__ import annotations

from typing import Any

from spl.dsl.parse_tree import Refused
from spl.dsl.tsm.reader import _Reader


def error_excerpt(text: str) -> str | None:
    """``text`` with the declarations textX need not read to word its syntax error
    reduced to their line breaks, or None when the reader reads ``text`` (or reads
    nothing textX could skip).

    Where the reader gives up, every declaration of a repetition (top-level elements,
    container members) it read to its end before that is one textX reads alike, and
    textX reads each at the position it starts, whatever precedes it. textX's error is
    its failure furthest into the text. The declaration being read when the reader gave
    up starts with a keyword textX matches as well, so that failure lies beyond its
    start, where no attempt made inside an earlier sibling reaches: those siblings are
    left out. Where the reader gave up between two declarations, the last one read is
    kept, without the declarations it holds (a container parses as well with no
    member): its optional trailing parts are tried right where the error is. The excerpt
    keeps the text's line breaks and, where a kept part resumes, its columns, so textX
    reports the same line, column and expectation while reading a declaration or two
    instead of the whole file (a 10,000-node file: well under a second instead of tens
    of seconds). When textX reads the excerpt without an error, the reader gave up on
    something textX reads (a bound of its own): the whole text must then be parsed.
    """
    reader = _ExcerptReader(text)
    try:
        reader.system()
    except Refused:
        pass
    else:
        return None
    innermost = len(reader.levels) - 1
    dropped = []
    for depth, level in enumerate(reader.levels):
        if depth == innermost and level:
            *level, (_, _, children) = level
            dropped += children  # the last one read is kept, what it holds is not
        dropped += level
    if not dropped:
        return None
    dropped.sort()
    parts, at = [], 0
    for start, end, _ in dropped:
        parts.append(text[at:start])
        removed = text[start:end]
        breaks = removed.count("\n")
        tail = len(removed) - removed.rfind("\n") - 1 if breaks else len(removed)
        parts.append("\n" * breaks + " " * tail)
        at = end
    parts.append(text[at:])
    return "".join(parts)


class _ExcerptReader(_Reader):
    """The reader noting, for each repetition being read, the declarations it read to
    their end (``levels``: the top level first, then inside the declaration being read),
    each as (start, end, the declarations it holds), for :func:`error_excerpt`."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.levels: list[list[tuple[int, int, list]]] = [[]]

    def item(self, rules: dict[str, Any], rule: Any, at: int, *optional: bool) -> Any:
        depth = len(self.levels)
        self.levels.append([])
        value = rule(self, at, *optional)
        children = self.levels[depth]
        del self.levels[depth:]  # read to its end: no longer in progress
        self.levels[-1].append((at, self.pos, children))
        return value
