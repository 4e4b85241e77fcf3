"""The models the editor works on: open documents (their unsaved texts), the files
they name, the last model each file parsed to, and what every name in them means.

A .rm names its .tsm and .fm (``tsm "x.tsm"``, ``fm "x.fm"``); those three files form
a *family* whose declarations are looked up together. Texts of files that are not
open come from disk. The checking thread stores models here; requests read them.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import threading
from dataclasses import dataclass
from typing import Any

from spl.lsp.occurrences import Occurrence, occurrences
from spl.lsp.positions import UTF16, LineIndex
from spl.lsp.symbols import Decl, SymbolIndex
from spl.lsp.tokens import Tokens, tokenize


@dataclass
class Document:
    uri: str
    path: str
    version: int
    text: str


def header_paths(path: str, tokens: Tokens) -> dict[str, str]:
    """The files a .rm names in its header: ``{"tsm": path, "fm": path}`` (absolute)."""
    found: dict[str, str] = {}
    items = tokens.tokens
    for before, token in itertools.pairwise(items):
        if before.is_word("tsm", "fm") and token.kind == "string":
            relative = token.string_value
            found.setdefault(
                before.text, os.path.normpath(os.path.join(os.path.dirname(path), relative))
            )
        if before.is_word("when"):
            break
    return found


class Project:
    """Open documents and parsed models, shared by the request handlers (event loop)
    and the checking thread."""

    def __init__(self) -> None:
        self.documents: dict[str, Document] = {}  # by absolute path
        self.models: dict[str, tuple[str, Any]] = {}  # path -> (text parsed, model)
        self.read_texts: dict[str, str] = {}  # path -> the text last checked, parsed or not
        self._lock = threading.Lock()
        self.encoding = UTF16  # the position encoding the client and server agreed on
        self._tokens: dict[str, tuple[str, Tokens]] = {}
        self._lines: dict[str, tuple[str, LineIndex]] = {}
        self._headers: dict[str, tuple[str, dict[str, str]]] = {}
        self._occurrences: dict[str, tuple[SymbolIndex, Tokens, list[Occurrence]]] = {}
        self._indexes: list[tuple[Any, Any, SymbolIndex]] = []  # the last few, newest last

    # -- texts ------------------------------------------------------------------------
    def text(self, path: str) -> str | None:
        """The editor's text of ``path`` when open, else the file's (None when unreadable)."""
        document = self.documents.get(path)
        if document is not None:
            return document.text
        try:
            with open(path, encoding="utf-8-sig", errors="replace") as handle:
                return handle.read()
        except OSError:
            return None

    def open_texts(self) -> dict[str, str]:
        return {path: d.text for path, d in self.documents.items()}

    def tokens(self, path: str, text: str | None = None) -> Tokens:
        text = self.text(path) if text is None else text
        text = text or ""
        with self._lock:
            cached = self._tokens.get(path)
            if cached is not None and cached[0] == text:
                return cached[1]
        tokens = tokenize(text, self.encoding)
        with self._lock:
            self._tokens[path] = (text, tokens)
        return tokens

    def header(self, path: str) -> dict[str, str]:
        """The files the .rm ``path`` names in its header (:func:`header_paths`), from
        the text before its first element: every change of a large .rm asks, and
        tokenizing all of a 5,000-line one took a tenth of a second."""
        text = self.text(path) or ""
        with self._lock:
            known = self._headers.get(path)
            if known is not None and known[0] == text:
                return known[1]
            whole = self._tokens.get(path)
        if whole is not None and whole[0] == text:
            tokens = whole[1]
        else:  # the shortest start of the text holding the first element's `when`
            end = 4096
            while True:
                tokens = tokenize(text[:end], self.encoding)
                if end >= len(text) or any(t.is_word("when") for t in tokens.tokens):
                    break
                end *= 4
        found = header_paths(path, tokens)
        with self._lock:
            self._headers[path] = (text, found)
        return found

    def lines(self, path: str) -> LineIndex:
        """The line index of ``path``'s text, without tokenizing it (what diagnostics
        need; a 10,000-node .tsm takes a second to tokenize)."""
        text = self.text(path) or ""
        with self._lock:
            cached = self._tokens.get(path)
            if cached is not None and cached[0] == text:
                return cached[1].lines
            known = self._lines.get(path)
            if known is not None and known[0] == text:
                return known[1]
        lines = LineIndex(text, self.encoding)
        with self._lock:
            self._lines[path] = (text, lines)
        return lines

    # -- models -------------------------------------------------------------------------
    def store_model(self, path: str, text: str, model: Any) -> None:
        """Keep the model ``text`` parsed to: requests use the last one that parsed."""
        with self._lock:
            self.models[path] = (text, model)

    def model(self, path: str) -> Any:
        found = self.models.get(path)
        return found[1] if found is not None else None

    def parsed_text(self, path: str) -> str | None:
        found = self.models.get(path)
        return found[0] if found is not None else None

    # -- families ------------------------------------------------------------------------
    def resolution_models(self, path: str) -> list[str]:
        """The .rm files that name ``path`` (open ones, and the .rm of its folder)."""
        candidates = [p for p in self.documents if p.endswith(".rm")]
        folder = os.path.dirname(path)
        with contextlib.suppress(OSError):  # a folder gone: only the open files count
            candidates += [
                os.path.join(folder, e.name) for e in os.scandir(folder) if e.name.endswith(".rm")
            ]
        found = []
        for candidate in dict.fromkeys(candidates):
            if candidate == path or path in self.header(candidate).values():
                found.append(candidate)
        return found

    def family(self, path: str) -> tuple[str | None, str | None, list[str]]:
        """(.tsm, .fm, files) whose declarations ``path``'s names reach, and the files
        where references to them can be (``path`` first)."""
        suffix = os.path.splitext(path)[1]
        files = [path]
        if suffix == ".rm":
            named = self.header(path)
            tsm, fm = named.get("tsm"), named.get("fm")
        else:
            tsm = path if suffix == ".tsm" else None
            fm = path if suffix != ".tsm" else None
            for rm in self.resolution_models(path):
                named = self.header(rm)
                tsm, fm = tsm or named.get("tsm"), fm or named.get("fm")
                files.append(rm)
        files += [p for p in (tsm, fm) if p]
        return tsm, fm, list(dict.fromkeys(files))

    def _line_of(self, path: str, line: int) -> str:
        return self.tokens(path).lines.line_text(line - 1)

    def index(self, tsm: str | None, fm: str | None) -> SymbolIndex:
        system = self.model(tsm) if tsm else None
        features = self.model(fm) if fm else None
        with self._lock:
            for known_system, known_features, index in self._indexes:
                if known_system is system and known_features is features:
                    return index
        index = SymbolIndex(system, features, self._line_of)
        with self._lock:
            self._indexes = [*self._indexes[-3:], (system, features, index)]
        return index

    def occurrences(self, path: str, index: SymbolIndex) -> list[Occurrence]:
        tokens = self.tokens(path)
        with self._lock:
            cached = self._occurrences.get(path)
        if cached is not None and cached[0] is index and cached[1] is tokens:
            return cached[2]
        found = occurrences(path, tokens, index)
        with self._lock:
            self._occurrences[path] = (index, tokens, found)
        return found

    def names_at(self, path: str, offset: int) -> tuple[Occurrence | None, SymbolIndex]:
        """The name at ``offset`` in ``path`` and the index of its family."""
        tsm, fm, _ = self.family(path)
        index = self.index(tsm, fm)
        for occurrence in self.occurrences(path, index):
            if occurrence.start <= offset <= occurrence.end:
                return occurrence, index
            if occurrence.start > offset:
                break
        return None, index

    def references(self, path: str, decls: tuple[Decl, ...]) -> list[tuple[str, Occurrence]]:
        """Every name in ``path``'s family that denotes one of ``decls``."""
        tsm, fm, files = self.family(path)
        index = self.index(tsm, fm)
        wanted = set(decls)
        return [
            (file, occurrence)
            for file in files
            for occurrence in self.occurrences(file, index)
            if wanted & set(occurrence.decls)
        ]
