"""What the fast readers of the grammars share: textX-shaped objects and a token cursor.

textX builds a metamodel from a grammar (a tenth of a second for fm.tx and rm.tx each)
and then interprets it one parsing expression at a time; ``spl check`` of a small
product line spent most of its time there. The readers of the three languages
(``tsm_reader``, ``fm_reader``, ``rm_reader``) follow their grammars by hand and
give objects the builders cannot tell from textX's: one class per grammar rule, named
after it (:func:`rule`), with the rule's attributes and ``_tx_position``.

:class:`Tokens` reads terminals the way textX's parser (arpeggio) does: blanks and
comments are skipped before every terminal, a keyword of a grammar built with
``autokwd`` must end at a word boundary, regular expressions are the grammar's own.
Ordered choice, optional parts and repetitions backtrack as in a PEG (:meth:`Tokens.first`,
:meth:`Tokens.optional`, :meth:`Tokens.repeated`); a reader that always knows from the
next token which alternative to take (the .tsm reader) never needs to. A reader
never reports a problem: where the text does not match it gives up (``None``) and
textX parses the text and words the syntax error.
"""

from __future__ import annotations

import bisect
import re
from collections.abc import Callable
from operator import itemgetter
from typing import Any

from spl.core.diagnostics import Location

# What textX skips before every terminal: its whitespace (arpeggio's default), then the
# alternatives of a grammar's Comment rule (the same in tsm.tx, fm.tx and rm.tx), each
# followed by whitespace.
WHITESPACE = "\t\n\r "
COMMENTS = (r"\/\/[^\n]*", r"\/\*(.|\n)*?\*\/")
SKIP = re.compile(rf"(?:[{WHITESPACE}]+|{COMMENTS[0]}|{COMMENTS[1]})*")
BLANKS = re.compile(rf"[{WHITESPACE}]*")  # a grammar without a Comment rule
# A keyword ``kw`` (matched as ``kw\b``, textX's autokwd) is next exactly when the run
# of word characters there is ``kw``.
_WORD = re.compile(r"\w*")
_new_tuple = tuple.__new__
try:  # the C accessor namedtuple's fields use
    from _collections import _tuplegetter as _field  # type: ignore[import-not-found]
except ImportError:  # pragma: no cover - an interpreter without it

    def _field(index: int, doc: str) -> Any:
        return property(itemgetter(index), doc=doc)


def rule(name: str, attributes: str) -> Any:
    """The class of a grammar rule's objects: its attributes, and where it starts.

    A tuple like a namedtuple's, made without namedtuple's code generation (the
    readers' ninety classes took some 14 ms of every ``spl check`` start that way)."""
    fields = ("position", *attributes.split())
    count = len(fields)

    def __new__(cls: type, *values: Any) -> Any:
        if len(values) != count:
            raise TypeError(f"{name} takes {count} values, got {len(values)}")
        return _new_tuple(cls, values)

    namespace: dict[str, Any] = {
        "__slots__": (),
        "__new__": __new__,
        "__repr__": _repr,
        "_fields": fields,
        "_make": classmethod(_make),
        "_tx_position": _field(0, "where the rule's first token starts"),
    }
    for index, field in enumerate(fields):
        namespace[field] = _field(index, field)
    return type(name, (tuple,), namespace)


class _Declared(type):
    """Makes a declared rule's class with :func:`rule` (see :class:`Rule`)."""

    def __new__(
        mcs, name: str, bases: tuple[type, ...], namespace: dict[str, Any], **_: Any
    ) -> Any:
        if not bases:  # Rule itself
            return super().__new__(mcs, name, bases, namespace)
        fields = list(namespace.get("__annotations__", {}))
        if fields[:1] != ["position"]:
            raise TypeError(f"{name}: a rule's first field is its position")
        made = rule(name, " ".join(fields[1:]))
        made.__module__ = namespace["__module__"]
        made.__qualname__ = namespace["__qualname__"]
        made.__doc__ = namespace.get("__doc__")
        return made


class Rule(metaclass=_Declared):
    """The base of a grammar rule declared as a class: ``position: int`` (the offset of
    its first token) and then its attributes, annotated as the grammar gives them.

    One declaration serves both: the type checker reads it as a ``typing.NamedTuple``
    (a module imports ``NamedTuple as Rule`` under TYPE_CHECKING), and at run time the
    class is made by :func:`rule` from the annotations' names."""


def _make(cls: type, values: Any) -> Any:
    """namedtuple's ``_make``: an object of ``cls`` from an iterable of its values, as
    the incremental reading rebuilds a tree at a new position."""
    return _new_tuple(cls, tuple(values))


def _repr(tree: Any) -> str:
    values = ", ".join(f"{f}={v!r}" for f, v in zip(tree._fields, tree, strict=True))
    return f"{type(tree).__name__}({values})"


class Refused(Exception):
    """The text does not match here (a reader that cannot backtrack gives up)."""


class TooDeep(Exception):
    """Nesting beyond what a reader follows: textX parses the text (and may refuse it
    for its own recursion), never another alternative of the reader."""


class Tokens:
    """One text read from the start; ``pos`` is where the next terminal is looked for.

    Every method that reads raises :class:`Refused` where the text holds something
    else, leaving ``pos`` to whoever tries another alternative."""

    skipped = SKIP  # what is skipped before a terminal

    def __init__(self, text: str) -> None:
        self.text = text
        self.pos = 0
        self._skipped = (-1, -1)  # the last skip: from, to

    # -- terminals -------------------------------------------------------------------
    def skip(self) -> int:
        """Where the next terminal starts: past blanks and comments."""
        start, end = self._skipped
        if start != self.pos:
            end = self.skipped.match(self.text, self.pos).end()  # type: ignore[union-attr]
            self._skipped = (self.pos, end)
        return end

    def at_end(self) -> bool:
        """Whether only blanks and comments are left (textX's EOF)."""
        return self.skip() == len(self.text)

    def word(self) -> tuple[int, str]:
        """Where the next token starts, and its run of word characters ('' if none)."""
        at = self.skip()
        return at, _WORD.match(self.text, at).group()  # type: ignore[union-attr]  # \w*

    def keyword(self, keyword: str) -> int:
        """An autokwd keyword: ``keyword`` ending at a word boundary."""
        at, word = self.word()
        if word != keyword:
            raise Refused
        self.pos = at + len(keyword)
        return at

    def at(self, literal: str) -> bool:
        return self.text.startswith(literal, self.skip())

    def punct(self, literal: str) -> int:
        """A literal matched as it is written (a keyword of a grammar without autokwd)."""
        at = self.skip()
        if not self.text.startswith(literal, at):
            raise Refused
        self.pos = at + len(literal)
        return at

    def match(self, regex: re.Pattern[str]) -> tuple[int, str]:
        at = self.skip()
        found = regex.match(self.text, at)
        if found is None:
            raise Refused
        self.pos = found.end()
        return at, found.group()

    def one_of(self, keywords: tuple[str, ...]) -> str:
        at, word = self.word()
        if word not in keywords:
            raise Refused
        self.pos = at + len(word)
        return word

    # -- PEG operators -----------------------------------------------------------------
    def optional(self, expression: Callable[[], Any], default: Any = None) -> Any:
        """``expression?``: its value, or ``default`` with nothing read."""
        start = self.pos
        try:
            return expression()
        except Refused:
            self.pos = start
            return default

    def repeated(self, expression: Callable[[], Any], separator: str | None = None) -> list[Any]:
        """``expression*`` (``expression*[separator]`` with a keyword separator)."""
        found: list[Any] = []
        while True:
            start = self.pos
            try:
                if separator is not None and found:
                    self.keyword(separator)
                found.append(expression())
            except Refused:
                self.pos = start
                return found

    def first(self, *alternatives: Callable[[], Any]) -> Any:
        """``A | B | ...``: the first alternative that matches."""
        start = self.pos
        for alternative in alternatives:
            try:
                return alternative()
            except Refused:
                self.pos = start
        raise Refused


class Positions:
    """Line and column of offsets in one text, counted as textX counts them."""

    def __init__(self, text: str, filename: str) -> None:
        self.filename = filename
        self._line_starts = [0] + [m.end() for m in re.finditer("\n", text)]

    def at(self, position: int) -> Location:
        index = bisect.bisect_right(self._line_starts, position) - 1
        return Location(self.filename, index + 1, position - self._line_starts[index] + 1)

    def of(self, tree: Any) -> Location:
        """Where a parse-tree object (the reader's or textX's) starts."""
        return self.at(tree._tx_position)
