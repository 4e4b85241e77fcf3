"""Every call of the language server into spl's checking, in one module.

The editor must report what ``spl check`` prints, so this module calls what
:mod:`spl.cli.commands.check` calls, through the server's workspace
(:class:`spl.dsl.workspace.Workspace`), whose unsaved texts stand in for the files:

* a model file in a product-line folder (one holding exactly one .rm) is checked as
  ``spl check FOLDER`` checks it (its parse errors, then the product-line checks SPL0xx
  of the whole line), and shows the findings located in it;
* any other .tsm, .fm or .rm is checked as ``spl check FILE`` (a .rm with the .tsm and
  .fm it names);
* a UVL or FeatureIDE .xml feature model as ``spl analyze`` and ``spl convert`` read it;
* a feature model checked on its own (any but a line's .fm) is then analysed as ``spl
  check FILE`` analyses it (:func:`feature_model_findings`), beside the checks
  (:mod:`spl.lsp.model_analyses`).

When spl gains one pipeline (load line, check selection, resolve, emit), this is the
one module to re-point.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from spl.core.diagnostics import Diagnostic, Location, ModelError
from spl.dsl.workspace import LastModels, Workspace

if TYPE_CHECKING:
    from spl.dsl.tsm.incremental import Trees

MODEL_SUFFIXES = (".tsm", ".fm", ".rm")
FEATURE_MODEL_SUFFIXES = (".uvl", ".xml")
SUFFIXES = MODEL_SUFFIXES + FEATURE_MODEL_SUFFIXES
_FEATUREIDE_ROOT = re.compile(r"<(featureModel|extendedFeatureModel)[\s>]")
_XML_ENCODING = re.compile(rb"""^<\?xml[^>]*encoding\s*=\s*["']([A-Za-z0-9._\-]+)["']""")


@dataclass(frozen=True)
class FileCheck:
    """What checking one file found: every diagnostic (a .rm's include those of the
    models it names, located there) and the model when it parsed."""

    path: str
    diagnostics: tuple[Diagnostic, ...]
    model: Any = None  # tsm System, fm FeatureModel, or rm ResolutionModelFiles
    # a feature model as its analysis reads it: a UVL model's plain objects, which keep
    # the Arithmetic and Type levels the pyecore model leaves out; else ``model``
    analysable: Any = None


# a line's findings, and the checks of its .tsm files (:meth:`LineChecks.check`)
Answer = tuple[tuple[Diagnostic, ...], tuple[FileCheck, ...]]


def product_line(path: str) -> str | None:
    """The product-line folder ``spl check`` checks ``path`` with: its folder when
    that holds exactly one .rm (and ``path`` is one of its .tsm, .fm or .rm files)."""
    if os.path.splitext(path)[1] not in MODEL_SUFFIXES:
        return None
    folder = os.path.dirname(path)
    try:
        with os.scandir(folder) as entries:
            models = [e.name for e in entries if e.name.endswith(".rm") and e.is_file()]
    except OSError:
        return None
    return folder if len(models) == 1 else None


def analysed_alone(path: str) -> bool:
    """Whether ``spl check`` analyses ``path`` as a feature model on its own: a .uvl or
    .xml, or a .fm outside a product-line folder (a line's .fm is judged by the line's
    checks, docs/commands.md, "spl check")."""
    suffix = os.path.splitext(path)[1].lower()
    if suffix in FEATURE_MODEL_SUFFIXES:
        return True
    return suffix == ".fm" and product_line(path) is None


def is_featureide(text: str) -> bool:
    """Whether an .xml text is a FeatureIDE feature model (other XML is not spl's)."""
    return _FEATUREIDE_ROOT.search(text[:4096]) is not None


def editor_workspace() -> Workspace:
    """The workspace one language server keeps from check to check: the .tsm texts it
    refused, the models its line checks built last, and what it keeps of each line's
    checks (docs/editors.md, "What the editor keeps")."""
    return Workspace(models=LastModels(), lines={})


def check_file(path: str, workspace: Workspace, trees: Trees | None = None) -> FileCheck:
    """``spl check FILE`` (or the feature-model reading of ``spl analyze``) on ``path``,
    reading the open files as ``workspace`` has them; a .tsm read incrementally from
    its last reading in ``trees``."""
    suffix = os.path.splitext(path)[1].lower()
    try:
        if suffix == ".tsm":  # what spl check FILE.tsm runs: the plain-object check
            from spl.dsl.tsm import language as tsm

            return FileCheck(path, (), tsm.check_file(path, trees, workspace))
        if suffix in MODEL_SUFFIXES:
            model = _parse_model(path, suffix, workspace)
            return FileCheck(path, (), model, model if suffix == ".fm" else None)
        if suffix == ".uvl":  # what spl check FILE.uvl reads: the plain model, then pyecore
            from spl.dsl.interop.uvl import ecore_of
            from spl.dsl.interop.uvl_reader import parse_uvl_plain
            from spl.dsl.workspace import text_of

            plain = parse_uvl_plain(text_of(path, workspace), path, Path(path).stem)
            return FileCheck(path, (), ecore_of(plain), plain)
        text = workspace.texts.get(os.path.abspath(path))
        if suffix == ".xml" and text is not None:
            model = _parse_featureide(path, text)
            return FileCheck(path, (), model, model)
        from spl.dsl.interop.formats import load_feature_model

        model = load_feature_model(path, workspace)
        return FileCheck(path, (), model, model)
    except ModelError as exc:
        return FileCheck(path, tuple(dict.fromkeys(exc.diagnostics)))


def feature_model_findings(result: FileCheck) -> tuple[Diagnostic, ...]:
    """What ``spl check FILE`` adds for a feature model that read without error: a void
    model's error at its root, else a warning at each dead feature's declaration
    (:mod:`spl.resolver.analysis.model_findings`, on SAT or z3 as ``spl analyze``)."""
    from spl.resolver.analysis.model_findings import feature_model_findings as findings

    return tuple(dict.fromkeys(findings(result.analysable)))


def _parse_model(path: str, suffix: str, workspace: Workspace) -> Any:
    from spl.pipeline import LANGUAGES

    language = importlib.import_module(LANGUAGES[suffix])
    if suffix == ".rm":  # what parse_file does, keeping the .tsm and .fm
        return language.load(path, workspace)
    return language.parse_file(path, workspace)


def _parse_featureide(path: str, text: str) -> Any:
    """An open FeatureIDE file: its text encoded as its XML declaration says, as the
    file on disk would be."""
    from spl.dsl.interop.featureide import parse_featureide

    data = text.encode("utf-8")
    declared = _XML_ENCODING.match(data)
    if declared:
        with contextlib.suppress(LookupError):  # an unknown encoding: the parser says so
            data = text.encode(declared.group(1).decode("ascii"), "xmlcharrefreplace")
    return parse_featureide(data, path, default_name=Path(path).stem)


def check_line(folder: str, workspace: Workspace) -> tuple[Diagnostic, ...]:
    """``spl check FOLDER`` through ``workspace``: every finding, in every file of the
    line, a product-line check's error shown as a warning (:func:`editor_severity`)."""
    from spl.pipeline import NothingToCheck, check_models

    try:
        _, found = check_models(Path(folder), count=False, workspace=workspace)
    except ModelError as exc:
        found = exc.diagnostics
    except NothingToCheck:
        found = []
    return tuple(editor_severity(d) for d in found)


class LineChecks:
    """``spl check FOLDER`` for the editor, run again only when its answer can change.

    A folder's check reads the line's model files, the files its .rm names and its
    listed products. The findings of the last few sets of those inputs used are kept,
    so an edit undone (and done again), or a file saved as it was, is answered at once,
    with the .tsm files' own checks of then: the models the editor's requests read are
    not built again either.
    Before the line is loaded, each .tsm is checked with the plain, incremental build
    (what ``spl check FILE.tsm`` runs): when it refuses the text, loading the line meets
    the same problems without building the model again (:func:`spl.dsl.tsm.language.parse_text`),
    and the answer is that of ``spl check FOLDER``, only sooner. A text that builds is
    checked in full, from what the last check built (the workspace's
    :class:`~spl.dsl.workspace.LastModels`): the line's pyecore model is built from
    the plain model just checked, taking over the declarations the edit left alone (moved
    where it moved them), a file the edit left alone is not built again, nor a .rm whose
    names still mean the same, an edited .rm builds only the elements the edit changed
    (:mod:`spl.dsl.rm.reuse`), the template's own facts are kept while it is the same
    model (:class:`~spl.resolver.resolution.product_line.TemplateFacts`), and a witness
    product whose resolution reads nothing the edit changed is not resolved again
    (:mod:`spl.resolver.line_checks.witnesses`)."""

    KEPT = 4  # input sets kept per folder

    def __init__(self, workspace: Workspace | None = None) -> None:
        """``workspace``: the server's (:func:`editor_workspace`, made here when not given)."""
        self.workspace = workspace if workspace is not None else editor_workspace()
        self._kept: dict[str, list[tuple[tuple[object, ...], Answer]]] = {}

    def check(
        self, folder: str, texts: Mapping[str, str], trees: Trees, inputs: set[str]
    ) -> Answer:
        """The folder's findings, and the .tsm files' own checks (the models of their
        texts), made now or kept from the check of the same inputs."""
        key = _snapshot(folder, inputs, texts)
        kept = self._kept.setdefault(folder, [])
        tsm_files = sorted(p for p in inputs if p.endswith(".tsm"))
        for at, (known, answer) in enumerate(kept):
            if known == key:  # the last used stay: an edit undone and done again
                kept.append(kept.pop(at))
                for path in tsm_files:  # the next change is read from this text
                    if path in texts:
                        trees.read(path, texts[path])
                return answer
        # the line is loaded from the plain models checked here, and witness products
        # are resolved again, and the .rm's own checks run again, only when what they
        # read changed
        workspace = self.workspace.reading(texts)
        plain = tuple(check_file(path, workspace, trees) for path in tsm_files)
        answer = check_line(folder, workspace), plain
        kept.append((key, answer))
        del kept[: -self.KEPT]
        return answer


def _snapshot(folder: str, inputs: set[str], texts: Mapping[str, str]) -> tuple[object, ...]:
    """What a folder's check reads, comparable: the editor's text of an open file, the
    size and modification time of any other file (a folder's, recursively)."""

    def state(path: str) -> object:
        if path in texts:
            return texts[path]
        try:
            info = os.stat(path)
        except OSError:
            return None
        if not os.path.isdir(path):
            return (info.st_size, info.st_mtime_ns, info.st_ino)
        with contextlib.suppress(OSError), os.scandir(path) as entries:
            return tuple(sorted((e.name, state(e.path)) for e in entries))
        return None

    open_here = {p for p in texts if os.path.dirname(p) == folder}
    return tuple((path, state(path)) for path in sorted(inputs | open_here))


def product_line_errors() -> frozenset[str]:
    """The codes of the product-line checks ``spl check`` reports as errors: an element
    no product activates (SPL010), a conflict a valid selection reaches (SPL012), a
    statement that fails in some product (SPL016)."""
    from spl.resolver.line_checks.conflicts import CONFLICT
    from spl.resolver.line_checks.dead_elements import DEAD_ELEMENT
    from spl.resolver.line_checks.lookups import PRODUCT_DEPENDENT

    return frozenset((DEAD_ELEMENT, CONFLICT, PRODUCT_DEPENDENT))


def editor_severity(diagnostic: Diagnostic) -> Diagnostic:
    """A product-line check's finding as the editor shows it: a warning on the element
    (docs/editors.md, "What the editor shows": the element is written correctly, the
    finding is about the line as a whole), with the text, code and place ``spl check`` gives it."""
    if diagnostic.severity == "error" and diagnostic.code in product_line_errors():
        return dataclasses.replace(diagnostic, severity="warning")
    return diagnostic


def internal_error(path: str, error: BaseException) -> Diagnostic:
    """An spl bug met while checking ``path``, said as ``spl`` says it (exit status 3)."""
    from spl import __version__

    return Diagnostic(
        Location(path, 1, 1),
        f"internal error in spl {__version__}: {type(error).__name__}: {error} "
        "(run spl check with SPL_DEBUG=1 for a traceback and report it)",
    )


def referenced_models(model: Any) -> list[str]:
    """The .tsm and .fm paths a parsed .rm names (absolute)."""
    base = os.path.dirname(str(model.path))
    return [
        os.path.normpath(os.path.join(base, relative))
        for relative in (model.rm.tsmPath, model.rm.fmPath)
    ]
