"""textX's ``model_from_str`` for any text the languages read, the empty one included.

Given an empty string, textX reads the file its ``file_name`` names instead: an editor's
emptied buffer was checked as the file saved on disk, and an empty unsaved file was an
internal error (FileNotFoundError). The empty text is passed as a string that is empty
but true, so textX parses it as it is.
"""

from __future__ import annotations

from typing import Any


class _EmptyText(str):
    __slots__ = ()

    def __bool__(self) -> bool:
        return True


def model_from_text(grammar: Any, text: str, filename: str) -> Any:
    """``grammar.model_from_str(text, file_name=filename)``, never reading ``filename``."""
    return grammar.model_from_str(text or _EmptyText(), file_name=filename)
