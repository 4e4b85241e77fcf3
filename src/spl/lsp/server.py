"""``spl lsp``: the Language Server Protocol server for .tsm, .fm and .rm (and UVL and
FeatureIDE .xml feature models, for diagnostics).

Diagnostics are checked in one background thread, a short while after the last
change (debounced), from the editor's unsaved texts; a feature model checked on its
own is then analysed in another (:mod:`spl.lsp.model_analyses`); requests (definition,
references, hover, completion, outline, formatting) are answered on the event loop
from the last models that parsed and the current text, so a long check never
blocks them. A failure while answering one request answers that request with an
error (pygls does) and the server goes on.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import threading
import traceback
from collections.abc import Iterable
from concurrent.futures import ThreadPoolExecutor
from contextlib import AbstractContextManager
from typing import Any

from lsprotocol import types
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path, to_fs_path

from spl import __version__
from spl.core.cyclic_gc import without_cyclic_gc
from spl.core.diagnostics import Diagnostic
from spl.dsl.tsm.incremental import Trees
from spl.dsl.workspace import Workspace
from spl.lsp import checking
from spl.lsp.model_analyses import Findings, ModelAnalyses
from spl.lsp.positions import LineIndex
from spl.lsp.project import Project
from spl.lsp.symbols import Decl

DEBOUNCE_SECONDS = 0.15  # quiet time after a change before the check starts
CHECK_STACK_BYTES = 64 * 1024 * 1024
SETTLE_SECONDS = 2.0  # how long navigation waits for the models of a change
SENT_SECONDS = 5.0  # how long garbage waits for a check's findings to be sent
SEVERITIES = {
    "error": types.DiagnosticSeverity.Error,
    "warning": types.DiagnosticSeverity.Warning,
    "info": types.DiagnosticSeverity.Information,
}
Unit = tuple[str, str]  # ("file", path) or ("line", folder): one check and its findings

logger = logging.getLogger(__name__)


def path_of(uri: str) -> str:
    return os.path.normpath(to_fs_path(uri) or uri)


def uri_of(path: str) -> str:
    return from_fs_path(path) or path


def collected_once_sent(loop: asyncio.AbstractEventLoop) -> AbstractContextManager[None]:
    """Cyclic garbage collection paused while a check runs, and run once what it
    published is sent. A check's models are garbage when it ends (a 10,000-node line's
    are a million objects), and collecting them took a quarter of a second before the
    editor saw the findings; after, it overlaps the user's next keystrokes."""

    def sent() -> None:
        done = threading.Event()
        with contextlib.suppress(RuntimeError):  # the loop is closed: nothing to wait for
            loop.call_soon_threadsafe(done.set)  # after the publications queued before
            done.wait(SENT_SECONDS)

    # all the check made is in the youngest generation: one pass over it
    return without_cyclic_gc("dropped", first=sent)


class SplLanguageServer(LanguageServer):
    def __init__(self) -> None:
        super().__init__("spl", __version__)
        self.project = Project()
        self.trees = Trees()  # the last reading of each .tsm: a change is read incrementally
        # what the editor keeps between checks, passed to each (docs/editors.md)
        self.spl_workspace = checking.editor_workspace()
        self.line_checks = checking.LineChecks(self.spl_workspace)  # the lines' last findings
        # deep models recurse deeply in textX and the analysis: the checking thread gets
        # the stack of a main thread, not a small thread default
        threading.stack_size(CHECK_STACK_BYTES)
        self.checker = ThreadPoolExecutor(max_workers=1, thread_name_prefix="spl-check")
        self.analyses = ModelAnalyses()  # lone feature models' analyses, beside the checks
        self.changed: set[str] = set()
        self.last_change = 0.0
        self.wake: asyncio.Event | None = None
        self.check_task: asyncio.Task | None = None
        self.settled: asyncio.Event | None = None  # set when no check is due or running
        self.stopping = False  # a shutdown request came
        self.exit_code = 0
        self.findings: dict[Unit, dict[str, tuple[Diagnostic, ...]]] = {}
        self.analysed: set[Unit] = set()  # units whose findings shown are an analysis's
        self.published: dict[str, tuple[Diagnostic, ...]] = {}

    # -- documents and checks ----------------------------------------------------------------
    def note_change(self, path: str) -> None:
        if self.stopping:
            return
        loop = asyncio.get_running_loop()
        if self.wake is None:
            self.wake = asyncio.Event()
            self.check_task = loop.create_task(self._check_loop())
        self._settled().clear()
        self.changed.add(path)
        self.last_change = loop.time()
        self.wake.set()

    async def _check_loop(self) -> None:
        loop = asyncio.get_running_loop()
        assert self.wake is not None
        while True:
            await self.wake.wait()
            while (quiet := self.last_change + DEBOUNCE_SECONDS - loop.time()) > 0:
                await asyncio.sleep(quiet)
            self.wake.clear()
            changed, self.changed = self.changed, set()
            try:
                units = self.units_reading(changed)
                texts = self.project.open_texts()
                await loop.run_in_executor(self.checker, self._check, units, texts, loop)
            except Exception:  # never the end of checking: the next change checks again
                logger.error("checking failed:\n%s", traceback.format_exc())
            if not self.changed:
                self._settled().set()

    def _settled(self) -> asyncio.Event:
        if self.settled is None:
            self.settled = asyncio.Event()
            self.settled.set()
        return self.settled

    async def wait_settled(self) -> None:
        """Wait (a little) for the checks of the last changes, so navigation reads the
        models of the text the user sees; a long check is not waited for."""
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(self._settled().wait(), SETTLE_SECONDS)

    def active_units(self) -> list[Unit]:
        """One check per open document: its product line's, or its own."""
        units: list[Unit] = []
        for path, document in self.project.documents.items():
            suffix = os.path.splitext(path)[1].lower()
            if suffix not in checking.SUFFIXES:
                continue
            if suffix == ".xml" and not checking.is_featureide(document.text):
                continue  # a launch file or any other XML: not a feature model
            folder = checking.product_line(path)
            units.append(("line", folder) if folder else ("file", path))
        return list(dict.fromkeys(units))

    def inputs(self, unit: Unit) -> set[str]:
        """The files a unit's check reads."""
        kind, where = unit
        if kind == "file":
            rms = [where] if where.endswith(".rm") else []
            found = {where}
        else:
            try:
                found = {os.path.join(where, e.name) for e in os.scandir(where)}
            except OSError:  # the folder is gone: its open files are all there is
                found = {p for p in list(self.project.documents) if os.path.dirname(p) == where}
            rms = [p for p in found if p.endswith(".rm")]
        for rm in rms:
            found |= set(self.project.header(rm).values())
        return found

    def units_reading(self, changed: set[str]) -> list[Unit]:
        """The active units that read a changed file, single files first (fast)."""
        units = [u for u in self.active_units() if self.inputs(u) & changed]
        return sorted(units, key=lambda u: u[0] != "file")

    def _check(self, units: list[Unit], texts: dict[str, str], loop: Any) -> None:
        """Run in the checking thread: each unit's findings, then the models requests use."""
        with collected_once_sent(loop):
            self._check_units(units, texts, loop)

    def _check_units(self, units: list[Unit], texts: dict[str, str], loop: Any) -> None:
        for unit in units:
            analysing = False
            try:
                found, analysing = self._findings(unit, texts, loop)
            except Exception as exc:  # an spl bug: shown on the document, never fatal
                logger.error("checking %s failed:\n%s", unit[1], traceback.format_exc())
                path = unit[1] if unit[0] == "file" else self._first_open(unit[1])
                found = {path: (checking.internal_error(path, exc),)}
            # a text that read is shown with its analysis, and the last analysis stays
            # until then; a syntax error, or its fix, is shown at once
            if not (analysing and unit in self.analysed):
                loop.call_soon_threadsafe(self.publish, unit, found)
        for path in self._model_files(texts):
            text = self.project.text(path)
            if text is not None and self.project.read_texts.get(path) != text:
                try:
                    result = checking.check_file(path, self.files(texts), self.trees)
                except Exception:
                    logger.error("parsing %s failed:\n%s", path, traceback.format_exc())
                    continue
                self._keep_models(result, texts, text)

    def files(self, texts: dict[str, str]) -> Workspace:
        """The workspace as checks of single files read it: the open ``texts`` standing
        in for the files, each model built afresh (requests keep and read them)."""
        return self.spl_workspace.reading(texts).of_files()

    def _first_open(self, folder: str) -> str:
        found = [p for p in list(self.project.documents) if os.path.dirname(p) == folder]
        return found[0] if found else os.path.join(folder, ".")

    def _findings(
        self, unit: Unit, texts: dict[str, str], loop: Any
    ) -> tuple[dict[str, Findings], bool]:
        """A unit's findings by file, and whether its analysis was started."""
        kind, where = unit
        analysing = False
        if kind == "file":
            text = self.project.text(where)
            result = checking.check_file(where, self.files(texts), self.trees)
            self._keep_models(result, texts, text)
            diagnostics: Iterable[Diagnostic] = result.diagnostics
            analysing = self._analyse(result, texts.get(where), loop)
        else:
            diagnostics, plain = self.line_checks.check(where, texts, self.trees, self.inputs(unit))
            for result in plain:  # the models requests use: not built again below
                self._keep_models(result, texts, self.project.text(result.path))
        return self._placed(unit, diagnostics), analysing

    def _analyse(self, result: checking.FileCheck, text: str | None, loop: Any) -> bool:
        """Start the analysis ``spl check FILE`` runs on a lone feature model that read
        (docs/editors.md, "How fast"); whether it was started."""
        path = result.path
        if text is None or result.diagnostics or result.analysable is None:
            return False
        if not checking.analysed_alone(path):
            return False

        def current() -> bool:
            return self.project.text(path) == text

        def done(path: str, text: str, found: Findings) -> None:
            loop.call_soon_threadsafe(self.publish_analysis, path, text, found)

        self.analyses.submit(text, result, current, done)
        return True

    def publish_analysis(self, path: str, text: str, found: Findings) -> None:
        """Show an analysis's findings while the text it analysed is the editor's."""
        if self.project.text(path) == text:
            unit = ("file", path)
            self.publish(unit, self._placed(unit, found), analysed=True)

    def _placed(self, unit: Unit, diagnostics: Iterable[Diagnostic]) -> dict[str, Findings]:
        """Findings by the file they are located in."""
        where = unit[1]
        # every file the check covers gets its findings, none when it has none
        found: dict[str, list[Diagnostic]] = {
            p: [] for p in self.inputs(unit) if p.endswith(checking.SUFFIXES)
        }
        for diagnostic in diagnostics:
            file = diagnostic.location.file if diagnostic.location else where
            file = os.path.normpath(os.path.abspath(file))
            if os.path.isdir(file):
                continue  # a folder-level finding has no place in an editor
            found.setdefault(file, []).append(diagnostic)
        return {file: tuple(dict.fromkeys(d)) for file, d in found.items()}

    def _keep_models(self, result: checking.FileCheck, texts: dict[str, str], text: Any) -> None:
        model = result.model
        if text is not None:
            self.project.read_texts[result.path] = text  # parsed (or refused): not again
        if model is None or text is None:
            return
        if hasattr(model, "rm"):  # a .rm loaded with its .tsm and .fm: keep those too
            for path, named in zip(
                checking.referenced_models(model), (model.tsm, model.fm), strict=True
            ):
                used = self.project.text(path)
                if used is not None and path.endswith((".tsm", ".fm")):
                    self.project.store_model(path, used, named)
        self.project.store_model(result.path, text, model)

    def _model_files(self, texts: dict[str, str]) -> list[str]:
        """The files whose models requests need: open ones and those open .rm files name."""
        found = [p for p in texts if p.endswith((".tsm", ".fm", ".uvl"))]
        found += [p for p in texts if p.endswith(".xml") and checking.is_featureide(texts[p])]
        for path in texts:
            if path.endswith(".rm"):
                found += self.project.header(path).values()
        return [p for p in dict.fromkeys(found) if os.path.isfile(p) or p in texts]

    def publish(
        self, unit: Unit, found: dict[str, tuple[Diagnostic, ...]], analysed: bool = False
    ) -> None:
        """Record a unit's findings (``analysed``: with its analysis's) and send every
        file whose diagnostics changed."""
        if unit in self.active_units():
            self.findings[unit] = found
            if analysed:
                self.analysed.add(unit)
            else:
                self.analysed.discard(unit)
        self.flush()

    def flush(self) -> None:
        active = set(self.active_units())
        self.findings = {u: f for u, f in self.findings.items() if u in active}
        self.analysed &= active
        merged: dict[str, list[Diagnostic]] = {}
        for found in self.findings.values():
            for path, diagnostics in found.items():
                merged.setdefault(path, []).extend(diagnostics)
        for path in sorted(set(merged) | set(self.published)):
            diagnostics = tuple(dict.fromkeys(merged.get(path, ())))
            if self.published.get(path) == diagnostics:
                continue
            document = self.project.documents.get(path)
            self.text_document_publish_diagnostics(
                types.PublishDiagnosticsParams(
                    uri=document.uri if document else uri_of(path),
                    diagnostics=self.to_lsp(path, diagnostics),
                    version=document.version if document else None,
                )
            )
            if path in merged:
                self.published[path] = diagnostics
            else:
                self.published.pop(path, None)

    def to_lsp(self, path: str, diagnostics: Iterable[Diagnostic]) -> list[types.Diagnostic]:
        lines = self.lines(path)
        return [
            types.Diagnostic(
                range=lines.word_range(d.location.line, d.location.col)
                if d.location
                else lines.range(0, 0),
                message=d.message,
                severity=SEVERITIES.get(d.severity, types.DiagnosticSeverity.Error),
                code=d.code,
                source="spl",
            )
            for d in diagnostics
        ]

    def lines(self, path: str) -> LineIndex:
        return self.project.lines(path)

    # -- navigation ----------------------------------------------------------------------------
    def location(self, decl: Decl) -> types.Location:
        lines = self.lines(decl.file)
        start = lines.spl_offset(decl.line, decl.col)
        end = start if decl.kind == "file" else start + len(decl.name)
        return types.Location(uri=uri_of(decl.file), range=lines.range(start, end))
