"""A line's resolution model kept from one of the editor's checks to the next, while the
models it was built against say the same to it.

Why: after an edit of a large .tsm the line's .rm is built again although it did not
change (a quarter of a second on a 10,000-node line), only because its references point
into the template. The editor's template keeps every declaration the edit left alone
(:mod:`spl.dsl.tsm.declarations`), so a .rm model whose references all point into those
still means the same, provided the names it is written with still find the same
elements: no declaration the edit changed, added or removed declares a name the .rm
text mentions (any word of it, strings and comments too). Its feature model must be the
very one it was built against (a .fm text is built once).

The last model built from each file against the editor's template is kept with its
references (in its workspace's :class:`~spl.dsl.workspace.LastModels`); the next build
forgets those references (pyecore records each one on the element referred to, which
would keep every model of the session alive).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from spl.core.diagnostics import DiagnosticSink
from spl.core.emf import forget_references, references
from spl.dsl.rm.models import referenced_models
from spl.dsl.tsm.declarations import BuiltTemplate, Key, declaration_of
from spl.metamodels import tsm as tsm_metamodel

if TYPE_CHECKING:
    from pathlib import Path

    from spl.dsl.workspace import LastModels, Workspace

WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


@dataclass
class KeptModel:
    text: str
    header: Any  # what the text's header names (its tsm and fm paths)
    where: dict[str, Any]  # where the header names them
    template: BuiltTemplate  # the template last found to mean the same to it
    feature_model: Any
    model: Any
    refers_to: dict[Key, Any]  # the declarations it refers into, by their element
    words: frozenset[str]


def still_built(
    workspace: Workspace | None, text: str, filename: str, base: Path
) -> tuple[Any, Any, Any] | None:
    """The model ``workspace`` keeps for ``filename`` built from ``text``, with the .tsm
    and .fm models it names (read as the workspace has them), while it means the same
    against them; else None."""
    last = workspace.models if workspace is not None else None
    found = last.resolution_models.get(filename) if last is not None else None
    if last is None or found is None or found.text != text:
        return None
    sink = DiagnosticSink()
    system, feature_model = referenced_models(found.header, found.where, base, sink, workspace)
    if sink.errors or not _still_meant(last, found, system, feature_model):
        return None
    return found.model, system, feature_model


def _still_meant(last: LastModels, found: KeptModel, system: Any, feature_model: Any) -> bool:
    """Whether ``found``'s model means the same against these models; if so, they are
    what it is compared with next."""
    template = last.built_template(system) if system is not None else None
    if template is None or feature_model is not found.feature_model:
        return False
    if any(template.elements.get(k) is not e for k, e in found.refers_to.items()):
        return False
    before, now = found.template, template
    changed = {
        k
        for k in before.elements.keys() | now.elements.keys()
        if before.elements.get(k) is not now.elements.get(k)
    }
    for declarations in (before.declarations.items, now.declarations.items):
        if any(declarations[k].names & found.words for k in changed if k in declarations):
            return False
    found.template = template
    return True


def remember(
    workspace: Workspace | None,
    text: str,
    filename: str,
    tree: Any,
    where: dict[str, Any],
    system: Any,
    feature_model: Any,
    model: Any,
    sink: DiagnosticSink,
) -> None:
    """Keep ``model``, built from ``text`` (when ``sink`` holds no error), when it refers
    into the template ``workspace`` keeps; forget the references of the one kept before."""
    last = workspace.models if workspace is not None else None
    template = last.built_template(system) if last is not None and system is not None else None
    if last is None or template is None:
        return
    previous = last.resolution_models.pop(filename, None)
    if previous is not None:
        forget_references(previous.model)
    if sink.errors:
        forget_references(model)
        return
    declarations = {id(element): key for key, element in template.elements.items()}
    package = tsm_metamodel().package
    refers_to: dict[Key, Any] = {}
    for _, _, target in references(model):
        if target.eClass.ePackage is not package:
            continue
        declaration = declaration_of(target)
        refers_to[declarations[id(declaration)]] = declaration
    words = frozenset(WORD.findall(text))
    last.resolution_models[filename] = KeptModel(
        text, tree, where, template, feature_model, model, refers_to, words
    )
