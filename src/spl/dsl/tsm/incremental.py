"""Reading a changed .tsm text from the reading of the text before the change.

Why: the editor re-checks a file on every change, and reading a 10,000-node .tsm costs
most of a second although a change touches one declaration. A change leaves the text
before it (the common prefix ``p``) and after it (the common suffix) as they were, so
the fast reader (``spl.dsl.tsm.reader``) reads the new text again but takes every
top-level element and container member it would read identically from the previous
reading instead:

* an element in the prefix whose reading looked at no character from ``p`` on (its
  text, the blanks after it and the word that follows, which the reader peeks at);
* an element of the suffix, where the reader arrives at the new place of an element
  the previous reading read there (reading is context-free: the same text from the
  same place gives the same element, whichever container it is in).

Everything else, the changed declarations, the container around them and the system,
is read as always. Elements taken over keep the positions they were read at (moving
every position after a change would cost as much as reading); :class:`Places` maps
those *stored* positions to offsets in the new text, and what is read afresh is
stored in a band of positions of its own so the two never collide. With positions
mapped, the tree is the one a full reading gives (``tests/test_tsm_incremental.py``
compares them on edits of every model). A text the reader refuses is refused here
too (textX then reads it).
"""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from spl.dsl.parse_tree import _WORD, SKIP, Refused
from spl.dsl.tsm import tree as tsm_tree
from spl.dsl.tsm.reader import _ELEMENTS, _MEMBERS, _Reader

CHUNK = 4096  # characters compared at once when looking for the common prefix and suffix
BAND = 1 << 40  # stored positions of one reading's fresh elements: offset + its band
MAX_SEGMENTS = 50_000  # beyond this many position segments, the text is read afresh
# The classes of parse-tree objects: the ones whose first field is a position.
_RULES = frozenset(
    value
    for value in [*vars(tsm_tree).values(), *tsm_tree.INTERFACE_RULES.values()]
    if isinstance(value, type) and issubclass(value, tuple) and hasattr(value, "_fields")
)
Spans = dict[int, tuple[Any, int]]  # offset of a start -> (element, offset of its end)
Made = dict[int, Any]  # id of an element -> its copy at another position


class Places:
    """Stored positions -> offsets in the text: disjoint segments of stored positions,
    each moved by its own shift (the change in length of the text before it)."""

    __slots__ = ("highs", "lows", "shifts")

    def __init__(self, lows: list[int], highs: list[int], shifts: list[int]) -> None:
        self.lows, self.highs, self.shifts = lows, highs, shifts

    @classmethod
    def identity(cls, length: int) -> Places:
        return cls([0], [length + 1], [0])

    def offset(self, stored: int) -> int:
        return stored + self.shifts[bisect_right(self.lows, stored) - 1]

    def changed(self, prefix: int, old_suffix_start: int, delta: int) -> Places:
        """The places of what a change keeps: stored positions read before the change
        (offsets under ``prefix``) stay, those after it (from ``old_suffix_start``)
        move by ``delta``, those in between are gone."""
        lows: list[int] = []
        highs: list[int] = []
        shifts: list[int] = []
        for low, high, shift in zip(self.lows, self.highs, self.shifts, strict=True):
            cut = min(high, prefix - shift)
            if low < cut:
                lows.append(low)
                highs.append(cut)
                shifts.append(shift)
            cut = max(low, old_suffix_start - shift)
            if cut < high:
                lows.append(cut)
                highs.append(high)
                shifts.append(shift + delta)
        return Places(lows, highs, shifts)

    def __len__(self) -> int:
        return len(self.lows)


@dataclass
class Reading:
    """One text read: its tree (positions as stored), the places of those positions,
    and where each top-level element and container member starts and ends (what the
    next reading may take over)."""

    text: str
    tree: Any
    places: Places
    generation: int = 0  # the band of positions the last fresh elements are stored in
    elements: Spans = field(default_factory=dict)
    members: Spans = field(default_factory=dict)


def read(text: str, previous: Reading | None = None) -> Reading | None:
    """The reading of ``text`` (its tree, positions mapped by its places, is
    ``tsm_reader.read(text)``), from ``previous`` when given; None where the reader
    leaves the text to textX."""
    if previous is not None and len(previous.places) > MAX_SEGMENTS:
        previous = None
    reader = _SplicingReader(text, previous)
    try:
        tree = reader.system()
    except Refused:
        return None
    if previous is None:
        return Reading(
            text, tree, Places.identity(len(text)), 0, reader.element_spans, reader.member_spans
        )
    return reader.banded(tree)


class Trees:
    """The last reading of each file, so a file read again after a change is read
    incrementally (the language server keeps one)."""

    def __init__(self) -> None:
        self._readings: dict[str, Reading] = {}

    def read(self, filename: str, text: str) -> tuple[Any, Places] | None:
        """The parse tree of ``text`` and its places (None where textX must read it).
        A text the reader refuses leaves the last reading in place: the fix of a
        syntax error is read from the text before it."""
        previous = self._readings.get(filename)
        reading = previous if previous is not None and previous.text == text else None
        if reading is None:
            reading = read(text, previous)
        if reading is None:
            return None
        self._readings[filename] = reading
        return reading.tree, reading.places


def common_prefix(old: str, new: str) -> int:
    """The length of the longest common prefix of ``old`` and ``new``."""
    limit = min(len(old), len(new))
    at = 0
    while at + CHUNK <= limit and old[at : at + CHUNK] == new[at : at + CHUNK]:
        at += CHUNK
    while at < limit and old[at] == new[at]:
        at += 1
    return at


def common_suffix(old: str, new: str, limit: int) -> int:
    """The length of the longest common suffix of ``old`` and ``new``, at most ``limit``."""
    size = 0
    while (
        size + CHUNK <= limit
        and old[len(old) - size - CHUNK : len(old) - size]
        == new[len(new) - size - CHUNK : len(new) - size]
    ):
        size += CHUNK
    while size < limit and old[len(old) - size - 1] == new[len(new) - size - 1]:
        size += 1
    return size


def located(value: Any, places: Places) -> Any:
    """A tree (or list of trees) with every stored position replaced by its offset:
    what a full reading of the text gives."""
    return relocated(value, lambda element: places.offset(element[0]))


def relocated(value: Any, move: Callable[[Any], int | None], made: Made | None = None) -> Any:
    """A tree (or list of trees) with each element at the position ``move`` gives for it
    (an element it gives None for is kept as it is, with all it holds); ``made`` maps the
    id of each element moved to its moved copy."""
    kind = type(value)
    if kind is list:
        return [relocated(item, move, made) for item in value]
    if kind in _RULES:
        position = move(value)
        if position is None:
            return value
        moved = kind._make(  # type: ignore[attr-defined]  # a rule's class (parse_tree.Rule)
            (position, *[relocated(v, move, made) for v in value[1:]])
        )
        if made is not None:
            made[id(value)] = moved
        return moved
    return value


class _SplicingReader(_Reader):
    """The fast reader, taking over the elements of a previous reading it may."""

    def __init__(self, text: str, previous: Reading | None) -> None:
        super().__init__(text)
        self.previous = previous
        self.element_spans: Spans = {}
        self.member_spans: Spans = {}
        self.taken: set[int] = set()  # ids of the elements taken over
        if previous is None:
            return
        old = previous.text
        self.prefix = common_prefix(old, text)
        suffix = common_suffix(old, text, min(len(old), len(text)) - self.prefix)
        self.delta = len(text) - len(old)
        self.suffix_start = len(text) - suffix  # in the new text
        self.places = previous.places.changed(self.prefix, len(old) - suffix, self.delta)

    def item(self, rules: dict[str, Any], rule: Any, at: int, *optional: bool) -> Any:
        if rules is _ELEMENTS:
            spans, old_spans = self.element_spans, self.previous and self.previous.elements
        elif rules is _MEMBERS:
            spans, old_spans = self.member_spans, self.previous and self.previous.members
        else:
            return rule(self, at, *optional)
        if old_spans:
            taken = self._take(old_spans, at)
            if taken is not None:
                self.pos = taken[1]
                spans[at] = taken
                self.taken.add(id(taken[0]))
                return taken[0]
        element = rule(self, at, *optional)
        spans[at] = (element, self.pos)
        return element

    def _take(self, old_spans: Spans, at: int) -> tuple[Any, int] | None:
        """The previous reading's element at offset ``at`` (and the offset of its end)
        where it reads identically; None where it must be read."""
        assert self.previous is not None
        if at >= self.suffix_start:
            found = old_spans.get(at - self.delta)
            if found is None:
                return None
            self._take_members(found[0], self.delta)
            return found[0], found[1] + self.delta
        found = old_spans.get(at)
        if found is None:
            return None
        old = self.previous.text
        peeked: int = SKIP.match(old, found[1]).end()  # type: ignore[union-attr]  # matches ''
        word: str = _WORD.match(old, peeked).group()  # type: ignore[union-attr]  # matches ''
        if peeked + max(1, len(word)) > self.prefix:
            return None
        self._take_members(found[0], 0)
        return found

    def _take_members(self, element: Any, delta: int) -> None:
        """A container taken over brings the spans of its members along."""
        if type(element) not in (tsm_tree.RobotContainer, tsm_tree.CloudContainer):
            return
        assert self.previous is not None
        old_places, old = self.previous.places, self.previous.members
        for member in element.members:
            start = old_places.offset(member.position)
            found = old.get(start)
            if found is not None:
                self.member_spans[start + delta] = (member, found[1] + delta)

    def banded(self, tree: Any) -> Reading:
        """The reading, its freshly read elements moved to stored positions of a band
        of their own (offset + band), so no stored position means two places."""
        assert self.previous is not None
        generation = self.previous.generation + 1
        band = _Band(generation * BAND, self.taken)
        name, elements = band.moved(tree.name), band.moved(tree.elements)
        # a system without a name starts where its first element does, taken over or not
        start = elements[0].position
        if name is not None:
            band.fresh.append(tree.position)
            start = tree.position + band.base
        places = self.places  # bands grow upwards: the fresh segments come last, in order
        for offset in sorted(set(band.fresh)):  # each its own segment: no change splits it
            places.lows.append(offset + band.base)
            places.highs.append(offset + band.base + 1)
            places.shifts.append(-band.base)
        return Reading(
            self.text,
            tsm_tree.System(start, name, elements),
            places,
            generation,
            band.spans(self.element_spans),
            band.spans(self.member_spans),
        )


class _Band:
    """Freshly read elements moved to the stored positions of one band (a class, not
    a recursive closure: that would be a reference cycle keeping the readings alive)."""

    def __init__(self, base: int, taken: set[int]) -> None:
        self.base = base
        self.taken = taken
        self.fresh: list[int] = []  # the offsets of the elements moved
        self.by_id: Made = {}  # id of an element read -> the element moved

    def moved(self, value: Any) -> Any:
        return relocated(value, self._position, self.by_id)

    def _position(self, element: Any) -> int | None:
        if id(element) in self.taken:
            return None
        self.fresh.append(element[0])
        return element[0] + self.base

    def spans(self, spans: Spans) -> Spans:
        return {at: (self.by_id.get(id(e), e), end) for at, (e, end) in spans.items()}
