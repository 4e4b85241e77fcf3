"""SPL015: listed products (``products/*.yaml``) that are not a valid, complete selection.

Each is a warning: located at the selected feature that contradicts the feature model,
at the file's first line for a choice it leaves open, or where the file is malformed.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from spl.core.diagnostics import Diagnostic, Location, ModelError
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.product_selection import ProductSelection, load_selection_file
from spl.resolver.resolution.selection import check_selection

UNRESOLVABLE_PRODUCT = "SPL015"


Listed = list[tuple[Path, "ProductSelection | ModelError"]]


def read_listed(line: ProductLine, unsaved: Mapping[str, str] | None = None) -> Listed:
    """Each listed product's selection, or the error reading it: read once for the checks
    that look at them (this one, and SPL019's sharing modes). ``unsaved``: an editor's
    texts, which stand in for the files (:func:`spl.core.diagnostics.model_text`)."""
    listed: Listed = []
    for path in line.product_files():
        try:
            listed.append((path, load_selection_file(path, unsaved)))
        except ModelError as exc:
            listed.append((path, exc))
    return listed


def unresolvable_products(line: ProductLine, listed: Listed) -> list[Diagnostic]:
    """Listed products that are not a valid, complete selection of the feature model."""
    found = []
    for path, selection in listed:
        try:
            if isinstance(selection, ModelError):  # the file did not read
                raise selection
            check = check_selection(
                line.formula,
                selection.features,
                selection.deselected,
                selection.locations,
                Location(str(path), 1, 1),
            )
        except ModelError as exc:  # unreadable, or unknown or contradictory names
            found.extend(_as_warnings(exc.diagnostics, f"product {path.stem}: "))
            continue
        if check.status == "invalid":  # located at the selected feature that contradicts
            found.extend(
                _as_warnings(
                    [d for d in check.diagnostics if d.severity == "error"],
                    f"product {selection.name} does not resolve: ",
                )
            )
        elif check.status == "incomplete":
            found.append(
                Diagnostic(
                    Location(str(path), 1, 1),
                    f"product {selection.name} does not resolve: open choice: "
                    f"{check.explanation()}",
                    "warning",
                    UNRESOLVABLE_PRODUCT,
                )
            )
    return found


def _as_warnings(diagnostics: list[Diagnostic], prefix: str) -> list[Diagnostic]:
    return [
        Diagnostic(d.location, prefix + d.message, "warning", UNRESOLVABLE_PRODUCT)
        for d in diagnostics
    ]
