"""The two models a resolution model names: its .tsm and its feature model.

A .rm file names them by paths relative to itself (``tsm "mapping.tsm"``,
``fm "features.uvl"``). Each is checked for its kind of file and existence, located at
its own header line, and parsed by its own language; the problems found in
either are reported together with the .rm file's, so a user sees every one at once.
"""

from __future__ import annotations

import importlib
import re
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from spl.core.diagnostics import DiagnosticSink, Location, ModelError
from spl.dsl.grammar_comments import COMMENT

if TYPE_CHECKING:
    from spl.dsl.parse_tree import Positions
    from spl.dsl.workspace import Workspace

# How each model named in a .rm header is read: the module and function of its
# language (imported when first needed) and the files it may be; a feature model may
# be written in .fm, UVL or FeatureIDE XML.
_READERS = {
    "tsm": ("spl.dsl.tsm.language", "parse_file", {".tsm"}),
    "fm": ("spl.dsl.interop.formats", "load_line_feature_model", {".fm", ".uvl", ".xml"}),
}


def header_lines(text: str, positions: Positions, start: Location) -> dict[str, Location]:
    """Where the header's ``tsm "..."`` and ``fm "..."`` are written (comments, which may
    mention either, blanked first); the model's start where one is not found."""
    plain = COMMENT.sub(lambda m: re.sub(r"[^\n]", " ", m.group()), text)
    found = {}
    for attr in ("tsm", "fm"):
        match = re.search(rf'(?<![\w."]){attr}\s*"', plain)
        found[attr] = positions.at(match.start()) if match else start
    return found


def referenced_models(
    tree: Any,
    where: Mapping[str, Location],
    base: Path,
    sink: DiagnosticSink,
    workspace: Workspace | None = None,
) -> tuple[Any, Any]:
    """(tsm.System, fm.FeatureModel) named by the parsed header ``tree`` (its ``tsm`` and
    ``fm`` lines written at ``where``), read as the editor's ``workspace`` has them when
    given; None for one that could not be read, its problems reported to ``sink``."""
    return (
        _load("tsm", tree, where["tsm"], base, sink, workspace),
        _load("fm", tree, where["fm"], base, sink, workspace),
    )


def _load(
    attr: str,
    tree: Any,
    where: Location,
    base: Path,
    sink: DiagnosticSink,
    workspace: Workspace | None,
) -> Any:
    """The model named by header field ``attr``, when it is an existing file of its kind."""
    module, function, suffixes = _READERS[attr]
    relative = getattr(tree, attr)
    path = (base / relative) if not Path(relative).is_absolute() else Path(relative)
    if path.suffix not in suffixes:
        sink.error(where, f"{attr} {str(path)!r}: expected a {' or '.join(sorted(suffixes))} file")
        return None
    if not path.is_file():
        sink.error(where, f"{attr} file {str(path)!r} not found")
        return None
    try:
        return getattr(importlib.import_module(module), function)(path, workspace)
    except ModelError as exc:
        sink.diagnostics.extend(exc.diagnostics)
        return None
