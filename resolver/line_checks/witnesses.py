"""The warnings of the witness products the line checks resolve, remembered from one check
of a line to the next (the editor's, after every change: :func:`remembering`).

Why: the dataflow check confirms each unfed input by resolving a witness product
(:mod:`.dataflow`), and on a 10,000-node line that one resolution is half a second of
every check, while most edits change nothing it reads: a new resolution element for a
feature the witness leaves out, a parameter of such an element.

A resolution reads the template, the feature model, and the resolution elements the
product activates, in file order (:mod:`spl.resolver.engine`); nothing else. So a
remembered resolution is reused when the template holds the very declarations it was
resolved from (the editor builds a .tsm text once,
``spl.dsl.model_reuse.reusing_models``, an edit of it builds again only the
declarations it changed, and no check changes a template), but for containers the
product drops whole, and the feature model and the active elements are equal in
content, their source locations included, since messages cite them
(:func:`spl.emf.fingerprint`). Only a resolution that succeeded without
completing the selection is remembered: a completed one activates elements of features
the witness does not name, and a failed one says nothing of which elements it read.
"""

from __future__ import annotations

import weakref
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import TYPE_CHECKING, Any

from spl.diagnostics import Diagnostic, ModelError
from spl.dsl.tsm import built_template
from spl.dsl.tsm_declarations import declaration_of
from spl.emf import fingerprint
from spl.metamodels import tsm
from spl.resolver.product_line import ProductLine
from spl.resolver.product_selection import selection_from_list

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

Witness = tuple[str, ...]
Warnings = tuple[Diagnostic, ...]


class WitnessResolutions:
    """The last resolutions of witness products of one line, by witness."""

    KEPT = 16  # witnesses remembered

    def __init__(self) -> None:
        # with each, weak references to the template's elements its key names by their
        # ids: an id is only compared while its element lives, and no template is held
        self._kept: dict[Witness, tuple[tuple, list[weakref.ref], Warnings]] = {}

    def warnings(self, line: ProductLine, witness: Witness) -> Warnings:
        """The warnings of the product ``witness``, resolved again only when what its
        resolution reads changed."""
        key, named = _inputs(line, witness)
        # an entry naming an element that is gone, or that the editor no longer builds
        # on (a declaration built afresh is a new element), can never be used again
        current = _elements(line.tsm)
        for known, (_, held, _) in list(self._kept.items()):
            if any((e := r()) is None or id(e) not in current for r in held):
                del self._kept[known]
        kept = self._kept.get(witness)
        if kept is not None and kept[0] == key:
            return kept[2]
        found, complete = _resolved(line, witness)
        self._kept.pop(witness, None)
        if complete:
            self._kept[witness] = (key, [weakref.ref(e) for e in named], found)
            while len(self._kept) > self.KEPT:
                del self._kept[next(iter(self._kept))]
        return found


_REMEMBERED: ContextVar[WitnessResolutions | None] = ContextVar("witnesses", default=None)


@contextmanager
def remembering(resolutions: WitnessResolutions) -> Iterator[None]:
    """Inside the block, witness resolutions come from and go to ``resolutions``."""
    token = _REMEMBERED.set(resolutions)
    try:
        yield
    finally:
        _REMEMBERED.reset(token)


def witness_warnings(line: ProductLine, witness: Witness) -> Warnings:
    """The warnings of the product ``witness`` (none when it does not resolve, which
    resolve, validate and the other checks report)."""
    remembered = _REMEMBERED.get()
    if remembered is not None:
        return remembered.warnings(line, witness)
    return _resolved(line, witness)[0]


def _resolved(line: ProductLine, witness: Witness) -> tuple[Warnings, bool]:
    """The product's warnings, and whether it resolved without completing the selection."""
    from spl.resolver.engine import resolve  # the engine imports the line checks' kin

    try:
        resolution = resolve(line, selection_from_list(",".join(witness)))
    except ModelError:
        return (), False
    return resolution.product.warnings, not resolution.completion.added


def _inputs(line: ProductLine, witness: Witness) -> tuple[tuple, list[Any]]:
    """What the resolution of ``witness`` reads: the template but the containers it drops
    whole, the feature model, and the elements it activates, in file order; and the
    template's elements that names by their ids."""
    selected = set(witness)
    package = tsm().package
    touched: set[int] = set()  # the template's declarations the active elements refer into

    def target(value: Any) -> object:
        if value.eClass.ePackage is not package:
            return _named(value)
        touched.add(id(declaration_of(value)))
        return id(value)

    elements = tuple(
        fingerprint(element, target)
        for element in line.rm.elements
        if (element.feature is not None and element.feature.name in selected)
        == element.activeIfSelected
    )
    template, named = _template(line.tsm, touched)
    return (template, fingerprint(line.fm, target), elements), named


def _elements(system: tsm_types.System) -> set[int]:
    """The ids of the template's declarations (of the System, without the editor's)."""
    built = built_template(system)
    return {id(e) for e in built.elements.values()} if built else {id(system)}


def _template(system: tsm_types.System, touched: set[int]) -> tuple[tuple, list[Any]]:
    """The template as a resolution reads it: each declaration (the very element, which
    the editor's next build takes over when an edit leaves it alone), but a container a
    product drops whole: one of optional nodes and stores only, which no other
    declaration and no active element refers into (it is pruned before anything looks
    at the product's architecture, ``tests/resolver/test_dropped_containers.py``).
    Without the editor's declarations, the System itself. With the elements named."""
    built = built_template(system)
    if built is None:
        return (id(system),), [system]
    items = built.declarations.items
    referred = set().union(*(d.refers_to for d in items.values()))
    read = [
        (key, built.elements[key])
        for key, d in items.items()
        if not (d.droppable and key not in referred and id(built.elements[key]) not in touched)
    ]
    return (built.declarations.own, tuple((k, id(e)) for k, e in read)), [e for _, e in read]


def _named(value: Any) -> tuple:
    """A feature-model element by the names (or, unnamed, the places) on its way up."""
    steps = []
    while value is not None:
        owner = value.eContainer()
        name = getattr(value, "name", None)
        if name is None and owner is not None:
            name = list(owner.eGet(value.eContainmentFeature())).index(value)
        steps.append((value.eClass.name, name))
        value = owner
    return tuple(steps)
