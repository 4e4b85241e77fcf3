"""The analysis of a feature model opened on its own, run beside the checks.

``spl check FILE`` analyses a lone .fm, .uvl or FeatureIDE .xml once it reads: a void
model is an error, a dead feature a warning (:func:`spl.lsp.checking.feature_model_findings`).
The editor shows the same findings, but what reading the text found must not wait for
them (docs/editors.md, "How fast"): the checking thread reads the text and shows its
syntax errors at once, and the analysis of a text that read runs here, in a thread of
its own, and is shown when it ends. A solver cannot be stopped halfway, so an analysis
the user has typed past is left out instead: one not yet started is replaced by that of
the newer text, or not started when the text has changed since, and the answer of one
that ran on an older text is not shown (the server compares the texts).
"""

from __future__ import annotations

import logging
import threading
import traceback
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

from spl.core.diagnostics import Diagnostic
from spl.lsp import checking

Findings = tuple[Diagnostic, ...]

logger = logging.getLogger(__name__)


class ModelAnalyses:
    """One thread analysing the latest text of each lone feature model."""

    def __init__(self) -> None:
        self._runner = ThreadPoolExecutor(max_workers=1, thread_name_prefix="spl-analysis")
        self._lock = threading.Lock()
        # path -> the latest text that read, what reading it gave, and whether the text
        # is still the editor's (asked before the analysis starts)
        self._waiting: dict[str, tuple[str, checking.FileCheck, Callable[[], bool]]] = {}

    def submit(
        self,
        text: str,
        result: checking.FileCheck,
        current: Callable[[], bool],
        done: Callable[[str, str, Findings], None],
    ) -> None:
        """Analyse ``result`` (``text`` read without error) and give ``done`` its path,
        text and findings, unless a newer text of the file comes first or ``current``
        says the editor's text is no longer ``text`` when its turn comes."""
        with self._lock:
            self._waiting[result.path] = (text, result, current)
        self._runner.submit(self._run, result.path, done)

    def _run(self, path: str, done: Callable[[str, str, Findings], None]) -> None:
        with self._lock:
            job = self._waiting.pop(path, None)
        if job is None:  # a newer text's analysis ran in this one's place
            return
        text, result, current = job
        if not current():  # typed past: the check of the newer text submits its own
            return
        try:
            found = checking.feature_model_findings(result)
        except Exception as exc:  # an spl bug: shown on the document, never fatal
            logger.error("analysing %s failed:\n%s", path, traceback.format_exc())
            found = (checking.internal_error(path, exc),)
        done(path, text, found)

    def shutdown(self) -> None:
        """Start no other analysis (one running ends on its own)."""
        with self._lock:
            self._waiting.clear()
        self._runner.shutdown(wait=False, cancel_futures=True)
