"""Models built once per text while the editor checks a product line
(:func:`reusing_models`).

The language server checks a line after every edit, and an edit changes one file: the
models of the others are the ones built before, and the edited .tsm is built again only
where the edit changed it (:mod:`spl.dsl.tsm_declarations`); a .rm whose names the edit
left alone is not built again either (:mod:`spl.dsl.rm`). Each language keeps, per file,
the text it last built and the model; this module holds the switch and those two
small operations.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any

_REUSING: ContextVar[bool] = ContextVar("reusing_models", default=False)

Built = dict[str, tuple[str, Any]]  # file -> (the text last built, its model)


@contextmanager
def reusing_models() -> Iterator[None]:
    """Inside the block, a text parsed or checked before (inside such a block) gives the
    same model again instead of a new one, and a changed text is built from what the
    last model of its file holds where the language can. The language server checks a
    product line this way after every edit: the plain model its check of an edited .tsm
    built is the one the line's pyecore model is built from, and an edit of the line's
    .rm or .fm builds none of a large .tsm again. Sound only for callers that leave the
    models as built: loading and checking a line do (the engine resolves a copy;
    tests/resolver/test_template_untouched.py holds them to it); a caller that edits a
    model must not use this."""
    token = _REUSING.set(True)
    try:
        yield
    finally:
        _REUSING.reset(token)


def reusing() -> bool:
    """Whether models are being reused (inside :func:`reusing_models`)."""
    return _REUSING.get()


def reused(built: Built, text: str, filename: str) -> Any:
    """The model ``text`` of ``filename`` built before, when reusing; else None."""
    kept = built.get(filename) if _REUSING.get() else None
    return kept[1] if kept is not None and kept[0] == text else None


def keep(built: Built, text: str, filename: str, model: Any) -> None:
    """Remember the model ``text`` built, when reusing."""
    if _REUSING.get():
        built[filename] = (text, model)
