"""What the editor keeps of a product line's checks from one check to the next
(:func:`remembering`): the warnings of the witness products it resolved
(:mod:`.witnesses`) and the findings of the checks that read only the .rm and .fm
(:mod:`.statements`). Each kind keeps what it needs to tell when it is still right;
outside the block, every check works afresh (``spl check`` on the command line).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, TypeVar

Kept = TypeVar("Kept")


class LineMemory:
    """What is kept of one line's checks, each kind by its class, made when first used."""

    def __init__(self) -> None:
        self._kept: dict[type, Any] = {}

    def of(self, kind: type[Kept]) -> Kept:
        found = self._kept.get(kind)
        if found is None:
            found = self._kept[kind] = kind()
        return found


_REMEMBERED: ContextVar[LineMemory | None] = ContextVar("line_memory", default=None)


@contextmanager
def remembering(memory: LineMemory) -> Iterator[None]:
    """Inside the block, the line's checks keep what they found in ``memory`` and take it
    from there while it is still right."""
    token = _REMEMBERED.set(memory)
    try:
        yield
    finally:
        _REMEMBERED.reset(token)


def remembered(kind: type[Kept]) -> Kept | None:
    """The kept ``kind`` of the line being checked inside :func:`remembering`; else None."""
    memory = _REMEMBERED.get()
    return memory.of(kind) if memory is not None else None
