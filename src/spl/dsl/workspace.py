"""The editor's workspace: what a check reads instead of the saved files, and what the
editor keeps from one check to the next (docs/editors.md, "What the editor keeps").

``spl lsp`` owns one workspace and passes it, with the texts of the moment, to every
reader and check that uses it; nothing else holds any of it. Without one (the command
line) every file is read from disk and every model is built afresh. It holds:

* ``texts``: the editor's unsaved texts, which stand in for the files on disk, so the
  editor's diagnostics are those of the very parsers ``spl check`` runs on saved files;
* ``refused``: the last .tsm text of each file that the plain build refused, with its
  problems (:class:`RefusedTexts`);
* ``models``: the models the line checks built last, per file (:class:`LastModels`),
  which the next check of a line builds on; None in the checks of single files, whose
  models the editor's requests keep and read;
* ``lines``: what the line checks keep of each product line (:class:`LineMemory`),
  or None where nothing is kept.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from spl.core.diagnostics import Diagnostic, ModelError, model_text

if TYPE_CHECKING:
    from spl.dsl.rm.reuse import KeptModel
    from spl.dsl.tsm.declarations import BuiltTemplate

Kept = TypeVar("Kept")
Built = dict[str, tuple[str, Any]]  # file -> (the text last built, its model)


class RefusedTexts:
    """The last text of each file that the plain .tsm build refused, with its problems.

    The pyecore build finds exactly those (tests/dsl/test_tsm_plain.py compares the two
    builds), so a later reading of the same text raises them without building anything:
    the editor checks a .tsm of a product line with the plain build, then loads the line
    (which reads the .tsm through the .rm, and on its own), and a refused 10,000-node
    text costs one plain build instead of three pyecore builds. ``spl check`` of a
    folder keeps one for its check: the line, then its files one by one."""

    def __init__(self) -> None:
        self._last: dict[str, tuple[str, tuple[Diagnostic, ...]]] = {}

    def raise_if_refused(self, text: str, filename: str) -> None:
        refused = self._last.get(filename)
        if refused is not None and refused[0] == text:
            raise ModelError(list(refused[1]))

    def refuse(self, text: str, filename: str, problems: list[Diagnostic]) -> None:
        self._last[filename] = (text, tuple(problems))

    def built(self, filename: str) -> None:
        """The file's text now builds: its old refusal is forgotten."""
        self._last.pop(filename, None)


class LastModels:
    """The models the editor's line checks built last, per file. A text built before
    gives the same model again, and a changed .tsm is built from what its file's last
    template holds where the edit left it alone (:mod:`spl.dsl.tsm.declarations`); a .rm
    whose names the edit left alone is not built again, and an edited one builds only the
    elements the edit changed (:mod:`spl.dsl.rm.reuse`). So the
    plain model the check of an edited .tsm built is the one the line's pyecore model is
    built from, and an edit of the line's .rm or .fm builds none of a large .tsm again.

    Sound only for callers that leave the models as built: loading and checking a line
    do (the engine resolves a copy; tests/resolver/test_template_untouched.py holds them
    to it); a caller that edits a model, or keeps one after the next build (a build
    takes over the elements of the template before it), must not use this."""

    def __init__(self) -> None:
        self.systems: Built = {}  # .tsm: the pyecore System
        self.checked: Built = {}  # .tsm: the plain System
        # the last template of each .tsm file, with its declarations: the next build of
        # the file takes over what an edit left alone
        self.templates: dict[str, BuiltTemplate] = {}
        self.feature_models: Built = {}  # .fm
        self.resolution_models: dict[str, KeptModel] = {}  # .rm, with what it refers to

    def built_template(self, system: Any) -> BuiltTemplate | None:
        """The declarations of ``system`` when it is the last template built of its file;
        None for any other, and for one whose declarations could not be told apart by
        their keys (the checks refuse such a template)."""
        found = next((b for b in self.templates.values() if b.system is system), None)
        return found if found is not None and found.declarations.unique else None


def last_built(built: Built, text: str, filename: str) -> Any:
    """The model ``text`` of ``filename`` built last; None when the last was another text."""
    kept = built.get(filename)
    return kept[1] if kept is not None and kept[0] == text else None


class LineMemory:
    """What is kept of one line's checks, each kind by its class (defined by the code that
    keeps it: :mod:`spl.resolver.line_checks.witnesses`,
    :mod:`spl.resolver.line_checks.statements`, the template's facts
    :class:`spl.resolver.resolution.product_line.TemplateFacts`), made when first used.
    Each kind keeps what it needs to tell when it is still right."""

    def __init__(self) -> None:
        self._kept: dict[type, Any] = {}

    def of(self, kind: type[Kept]) -> Kept:
        found = self._kept.get(kind)
        if found is None:
            found = self._kept[kind] = kind()
        return found


@dataclass(frozen=True, eq=False)  # one workspace is itself: its stores change
class Workspace:
    """One check's view of the editor's workspace: the texts of the moment, and the
    stores the editor keeps (shared by every view made of one workspace)."""

    texts: Mapping[str, str] = field(default_factory=dict)  # by absolute path
    refused: RefusedTexts = field(default_factory=RefusedTexts)
    models: LastModels | None = None
    lines: dict[str, LineMemory] | None = None  # by the line's folder (absolute)

    def reading(self, texts: Mapping[str, str] | Mapping[Path, str]) -> Workspace:
        """This workspace with the editor's unsaved ``texts`` standing in for the files."""
        unsaved = {os.path.abspath(path): text for path, text in texts.items()}
        return dataclasses.replace(self, texts=unsaved)

    def of_files(self) -> Workspace:
        """This workspace for checks of single files: their models are built afresh (the
        editor's requests keep them) and no line's memory is kept."""
        return dataclasses.replace(self, models=None, lines=None)

    def text(self, path: str | Path) -> str:
        """The text of a model file: the editor's when it is open, else the file's."""
        return model_text(path, self.texts)

    def line_memory(self, folder: str | Path) -> LineMemory | None:
        """What is kept of the checks of the line in ``folder``; None when nothing is."""
        if self.lines is None:
            return None
        return self.lines.setdefault(os.path.abspath(folder), LineMemory())


def text_of(path: str | Path, workspace: Workspace | None) -> str:
    """The text of a model file, as ``workspace`` has it (else the file's)."""
    return model_text(path) if workspace is None else workspace.text(path)
