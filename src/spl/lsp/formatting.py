"""Formatting a .tsm or .fm with spl's printers (the text ``resolved.tsm`` and ``spl
convert`` write). The printers write a model, not a text: comments are not part of a
model, so a text holding comments is not formatted rather than losing them."""

from __future__ import annotations

import os
from typing import Any

from spl.lsp.tokens import has_comments


def formatted(path: str, text: str, model: Any) -> tuple[str | None, str]:
    """(the printed text, "") or (None, why it is not formatted)."""
    suffix = os.path.splitext(path)[1].lower()
    name = os.path.basename(path)
    if suffix not in (".tsm", ".fm"):
        return None, f"{name}: spl formats .tsm and .fm files (there is no printer for {suffix})"
    if model is None:
        return None, f"{name}: not formatted: the file has errors"
    if has_comments(text):
        return None, f"{name}: not formatted: the printer would drop its comments"
    if suffix == ".tsm":
        from spl.dsl.tsm.printer import print_model as print_system

        return print_system(model), ""
    from spl.dsl.fm.printer import print_model

    return print_model(model), ""
