"""A witness resolution, or the dataflow check's findings, the editor keeps serve a
template whose declarations only moved (``spl.resolver.line_checks.witnesses``,
``moved_findings``): each warning located in the template moves
with the declaration it is in, and the resolution is made again when a warning is in
no declaration read, when declarations overlapping it moved apart, or when its message
cites a place in the template."""

from __future__ import annotations

from typing import NamedTuple

from spl.core.diagnostics import Diagnostic, Location
from spl.resolver.line_checks.witnesses import Lines, moved_findings

FILE = "line/line.tsm"


def warning(line: int, message: str = "unfed", file: str = FILE) -> Diagnostic:
    return Diagnostic(Location(file, line, 9), message, "warning", "SPL045")


class Kept(NamedTuple):
    lines: Lines
    warnings: tuple[Diagnostic, ...]


def _moved(kept: Kept, lines: Lines, file: str) -> tuple[Diagnostic, ...] | None:
    return moved_findings(kept.lines, kept.warnings, lines, file)


def remembered(*warnings: Diagnostic) -> Kept:
    # two containers: A (lines 3-10, a node in it at 5-8) and B (12-20)
    lines = {("containers", "A"): (3, 3), ("containers", "A", "nodes", "N"): (5, 8)}
    lines[("containers", "B")] = (12, 20)
    return Kept(lines, warnings)


def test_warnings_move_with_their_declarations() -> None:
    kept = remembered(warning(6), warning(15), warning(2, file="line/line.rm"))
    now = {("containers", "A"): (3, 3), ("containers", "A", "nodes", "N"): (7, 10)}
    now[("containers", "B")] = (14, 22)
    moved = _moved(kept, now, FILE)
    assert moved is not None
    assert [(w.location.file, w.location.line, w.location.col) for w in moved] == [
        (FILE, 8, 9),
        (FILE, 17, 9),
        ("line/line.rm", 2, 9),  # another file: where it was
    ]
    assert [w.message for w in moved] == ["unfed"] * 3
    assert _moved(kept, remembered().lines, FILE) is kept.warnings  # nothing moved


def test_a_warning_no_moved_declaration_holds_is_resolved_again() -> None:
    now = {("containers", "A"): (4, 4), ("containers", "A", "nodes", "N"): (6, 9)}
    now[("containers", "B")] = (13, 21)
    assert _moved(remembered(warning(11)), now, FILE) is None  # between A's node and B
    assert _moved(remembered(warning(25)), now, FILE) is None  # after every one
    cited = warning(15, f"fed only from {FILE}:5:5")
    assert _moved(remembered(cited), now, FILE) is None  # cites a place that moved


def test_overlapping_declarations_that_moved_apart_resolve_again() -> None:
    kept = Kept({("a",): (3, 9), ("b",): (5, 6)}, (warning(4),))
    assert _moved(kept, {("a",): (4, 10), ("b",): (6, 7)}, FILE) is not None  # together
    assert _moved(kept, {("a",): (4, 10), ("b",): (8, 9)}, FILE) is None
