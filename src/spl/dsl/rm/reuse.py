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

An edit of the .rm itself builds only the elements it changed (:func:`taken_over`): the
others are taken over from the last model, their lines moved where the edit moved them
(``tests/dsl/test_rm_elements.py`` compares the model, element by element and place by
place, with a full build through chains of edits).

The last model built from each file against the editor's template is kept with its
references (in its workspace's :class:`~spl.dsl.workspace.LastModels`); the next build
forgets those of the elements it did not take over (pyecore records each one on the
element referred to, which would keep every model of the session alive).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

from spl.core.diagnostics import DiagnosticSink
from spl.core.emf import forget_references, move_lines, references
from spl.dsl.rm.models import referenced_models
from spl.dsl.rm.names import CHANGING_STATEMENTS
from spl.dsl.tsm.declaration_paths import Key, declaration_of
from spl.dsl.tsm.declarations import BuiltTemplate
from spl.metamodels import tsm as tsm_metamodel

if TYPE_CHECKING:
    from pathlib import Path

    from spl.dsl.workspace import LastModels, Workspace

WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
BLANKS = "\t\n\r "  # what the grammar skips besides comments (spl.dsl.parse_tree)


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
    # per element, by its id: the element, and the declarations it refers into
    by_element: dict[int, tuple[Any, dict[Key, Any]]]


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


class _Written(NamedTuple):
    """A resolution element as written: its first line and column, its text from its
    first token to the next element's (blanks at the end left out), and whether it has a
    statement that changes what the names after it mean."""

    line: int
    column: int
    text: str
    changing: bool


def taken_over(
    workspace: Workspace | None,
    text: str,
    filename: str,
    tree: Any,
    system: Any,
    feature_model: Any,
) -> list[Any]:
    """Per element of ``tree`` (``text`` read), the element of the model the workspace
    keeps for ``filename`` to take over, its lines moved to where it is now, or None to
    build it; empty when none is taken over.

    An element's build reads its text, the .tsm and .fm models, and what the elements
    before it left of the names (:class:`spl.dsl.rm.names.Names`: migrations, topics
    created). The kept model has no error, so each of its elements was built in full.
    With the same .tsm and .fm models, an element written as before (the same text at
    the same column) is built the same when the elements before it are the same, or
    when those the edit changed, before and after it, change no names. The elements
    before the first one the edit changed, and after the last one, are taken over."""
    last = workspace.models if workspace is not None else None
    found = last.resolution_models.get(filename) if last is not None else None
    if last is None or found is None or found.feature_model is not feature_model:
        return []
    if found.template.system is not system or last.built_template(system) is not found.template:
        return []  # (remember, after the build, forgets what it did not take over)
    before, now = _written(found.text, found.header), _written(text, tree)
    elements = list(found.model.elements)
    if len(elements) != len(before):
        return []
    same = min(len(before), len(now))
    first = next((i for i in range(same) if before[i][1:3] != now[i][1:3]), same)
    last_ones = next(
        (i for i in range(same - first) if before[-1 - i][1:3] != now[-1 - i][1:3]), same - first
    )
    changed = before[first : len(before) - last_ones] + now[first : len(now) - last_ones]
    if any(element.changing for element in changed):
        last_ones = 0  # the names the elements after them read may mean something else
    taken: list[Any] = [None] * len(now)
    pairs = [(i, i) for i in range(first)]
    pairs += [(len(now) - 1 - i, len(before) - 1 - i) for i in range(last_ones)]
    for at, was in pairs:
        moved = now[at].line - before[was].line
        if moved:
            move_lines(elements[was], moved)
        taken[at] = elements[was]
    return taken if pairs else []


def _written(text: str, tree: Any) -> list[_Written]:
    """Each resolution element of ``tree`` as written in ``text`` (:class:`_Written`)."""
    starts = [element._tx_position for element in tree.elements]
    found, line, at = [], 1, 0
    for index, (start, element) in enumerate(zip(starts, tree.elements, strict=True)):
        line += text.count("\n", at, start)
        at = start
        column = start - text.rfind("\n", 0, start)
        end = starts[index + 1] if index + 1 < len(starts) else len(text)
        changing = any(type(s).__name__ in CHANGING_STATEMENTS for s in element.statements)
        found.append(_Written(line, column, text[start:end].rstrip(BLANKS), changing))
    return found


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
    if previous is not None:  # its elements but those the new model took over
        for element in previous.model.elements:
            if element.eContainer() is previous.model:
                forget_references(element)
    if sink.errors:
        forget_references(model)
        return
    # what each element refers into: an element taken over refers where it did
    before = previous.by_element if previous is not None and previous.template is template else {}
    declarations: dict[int, Key] = {}
    package = tsm_metamodel().package
    by_element: dict[int, tuple[Any, dict[Key, Any]]] = {}
    refers_to: dict[Key, Any] = {}
    for element in model.elements:  # (the model itself refers to nothing)
        kept = before.get(id(element))
        if kept is None or kept[0] is not element:
            if not declarations:
                declarations = {id(e): key for key, e in template.elements.items()}
            into = {}
            for _, _, target in references(element):
                if target.eClass.ePackage is package:
                    declaration = declaration_of(target)
                    into[declarations[id(declaration)]] = declaration
            kept = (element, into)
        by_element[id(element)] = kept
        refers_to.update(kept[1])
    words = frozenset(WORD.findall(text))
    last.resolution_models[filename] = KeptModel(
        text, tree, where, template, feature_model, model, refers_to, words, by_element
    )
