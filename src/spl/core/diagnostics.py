"""Located diagnostics shared by every stage of the pipeline.

Every problem a user can fix is reported as ``file:line:col: severity: message`` so
editors and CI logs can jump to it; stages collect all problems of a file and raise
them together in one :class:`ModelError` instead of stopping at the first.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

Severity = Literal["error", "warning", "info"]


@dataclass(frozen=True, order=True)
class Location:
    file: str
    line: int = 0
    col: int = 0

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


@dataclass(frozen=True)
class Diagnostic:
    location: Location | None
    message: str
    severity: Severity = "error"
    code: str | None = None

    def __str__(self) -> str:
        where = f"{self.location}: " if self.location else ""
        code = f" [{self.code}]" if self.code else ""
        return f"{where}{self.severity}: {self.message}{code}"

    def as_dict(self) -> dict[str, Any]:
        loc = self.location
        return {
            "file": loc.file if loc else None,
            "line": loc.line if loc else None,
            "col": loc.col if loc else None,
            "severity": self.severity,
            "code": self.code,
            "message": self.message,
        }


class ModelError(Exception):
    """Raised with every error found; the command line prints them and exits 1."""

    def __init__(self, diagnostics: list[Diagnostic]) -> None:
        self.diagnostics = diagnostics
        super().__init__("\n".join(str(d) for d in diagnostics))


@dataclass
class DiagnosticSink:
    """Collects diagnostics while a model is checked; ``raise_if_errors`` ends the stage."""

    diagnostics: list[Diagnostic] = field(default_factory=list)

    def error(self, location: Location | None, message: str, code: str | None = None) -> None:
        self.diagnostics.append(Diagnostic(location, message, "error", code))

    def warning(self, location: Location | None, message: str, code: str | None = None) -> None:
        self.diagnostics.append(Diagnostic(location, message, "warning", code))

    def info(self, location: Location | None, message: str, code: str | None = None) -> None:
        self.diagnostics.append(Diagnostic(location, message, "info", code))

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == "error"]

    def raise_if_errors(self) -> None:
        if self.errors:
            raise ModelError(sorted(self.errors, key=_order))


def _order(d: Diagnostic) -> tuple:
    loc = d.location or Location("")
    return (loc.file, loc.line, loc.col, d.message)


def location_of(element: Any) -> Location | None:
    """The source location recorded on a model element (the metamodels' ``Located``)."""
    file = getattr(element, "srcFile", None)
    if not file:
        return None
    return Location(file, element.srcLine or 0, element.srcCol or 0)


def model_text(path: str | Path, unsaved: Mapping[str, str] | None = None) -> str:
    """The text of a model or selection file (UTF-8, a byte order mark dropped); a file
    that is not UTF-8 is a located error at the first bad byte, not a crash. ``unsaved``
    (by absolute path): an editor's texts, which stand in for the files on disk, so the
    language server (``spl lsp``) checks its unsaved buffers with the very parsers
    ``spl check`` runs on the saved files (:class:`spl.dsl.workspace.Workspace`)."""
    if unsaved and (text := unsaved.get(os.path.abspath(path))) is not None:
        return _line_breaks(text.removeprefix("\ufeff"))
    path = Path(path)
    data = _read(path)
    try:
        return _line_breaks(data.decode("utf-8-sig"))
    except UnicodeDecodeError as exc:
        start = exc.start + (3 if data.startswith(b"\xef\xbb\xbf") else 0)
        line = data.count(b"\n", 0, start) + 1
        col = start - (data.rfind(b"\n", 0, start) + 1) + 1
        where = Location(str(path), line, col)
        raise ModelError([Diagnostic(where, f"file is not UTF-8 text ({exc.reason})")]) from None


def _read(path: Path) -> bytes:
    """The bytes of a regular file, or a located error saying why not: a folder named like
    a model, a named pipe (reading it would block for ever), a dangling link or a link
    loop, a file without permission."""
    if path.is_file():
        try:
            return path.read_bytes()
        except OSError as exc:
            reason = exc.strerror or type(exc).__name__
    else:
        reason = "a folder" if path.is_dir() else "not a file" if path.exists() else "missing"
    raise ModelError([Diagnostic(Location(str(path), 1, 1), f"cannot read: {reason}")])


def _line_breaks(text: str) -> str:
    """Old Mac line ends (a lone carriage return) as line feeds, one character for one, so
    every position keeps its offset and is counted on the line an editor shows it on (the
    parsers count only line feeds: each such file was one line)."""
    return _LONE_CR.sub("\n", text) if "\r" in text else text


_LONE_CR = re.compile(r"\r(?!\n)")


def counted(count: int, noun: str) -> str:
    """``1 bridge``, ``4 bridges``: the counts in every summary line read as English."""
    return f"{count} {noun}{'' if count == 1 else 's'}"
