"""A line's resolution model kept from one of the editor's checks to the next, while the
models it was built against say the same to it (:func:`spl.dsl.model_reuse.reusing_models`).

Why: after an edit of a large .tsm the line's .rm is built again although it did not
change (a quarter of a second on a 10,000-node line), only because its references point
into the template. The editor's template keeps every declaration the edit left alone
(:mod:`spl.dsl.tsm_declarations`), so a .rm model whose references all point into those
still means the same, provided the names it is written with still find the same
elements: no declaration the edit changed, added or removed declares a name the .rm
text mentions (any word of it, strings and comments too). Its feature model must be the
very one it was built against (a .fm text is built once).

The last model built from each file against the editor's template is kept with its
references; the next build forgets those references (pyecore records each one on the
element referred to, which would keep every model of the session alive).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from spl.dsl.tsm import built_template
from spl.dsl.tsm_declarations import BuiltTemplate, Key, declaration_of
from spl.emf import forget_references, references
from spl.metamodels import tsm as tsm_metamodel

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


_KEPT: dict[str, KeptModel] = {}


def kept(text: str, filename: str) -> KeptModel | None:
    """The model kept for ``filename`` when it was built from ``text``."""
    found = _KEPT.get(filename)
    return found if found is not None and found.text == text else None


def still_meant(found: KeptModel, system: Any, feature_model: Any) -> bool:
    """Whether ``found``'s model means the same against these models; if so, they are
    what it is compared with next."""
    template = built_template(system) if system is not None else None
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
    text: str,
    filename: str,
    tree: Any,
    where: dict[str, Any],
    system: Any,
    feature_model: Any,
    model: Any,
    built: bool,
) -> None:
    """Keep ``model``, built from ``text`` (``built``: without errors), when it refers
    into the editor's template; forget the references of the one kept before."""
    template = built_template(system) if system is not None else None
    if template is None:
        return
    previous = _KEPT.pop(filename, None)
    if previous is not None:
        forget_references(previous.model)
    if not built:
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
    _KEPT[filename] = KeptModel(text, tree, where, template, feature_model, model, refers_to, words)
