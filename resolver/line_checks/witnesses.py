"""The warnings of the witness products the line checks resolve, remembered from one check
of a line to the next (the editor's, after every change: :func:`remembering`).

Why: the dataflow check confirms each unfed input by resolving a witness product
(:mod:`.dataflow`), and on a 10,000-node line that one resolution is half a second of
every check, while most edits change nothing it reads: a new resolution element for a
feature the witness leaves out, a parameter of such an element.

A resolution reads the template, the feature model, and the resolution elements the
product activates, in file order (:mod:`spl.resolver.engine`); nothing else. So a
remembered resolution is reused when the template holds the very declarations it was
resolved from (the editor builds a .tsm text once, ``spl.dsl.tsm.reusing_models``, an
edit of it builds again only the declarations it changed, and no check changes a
template), but for containers the product drops whole, and the feature model and the
active elements are equal in content, their source locations included, since messages
cite them (:func:`spl.emf.fingerprint`). Only a resolution that succeeded without
completing the selection is remembered: a completed one activates elements of features
the witness does not name, and a failed one says nothing of which elements it read.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import TYPE_CHECKING, Any

from spl.diagnostics import Diagnostic, ModelError
from spl.dsl.tsm import built_template
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

    KEPT = 16  # witnesses remembered, each with the template it was resolved from

    def __init__(self) -> None:
        # the template is kept alive: the key names its elements by their ids
        self._kept: dict[Witness, tuple[tsm_types.System, tuple, Warnings]] = {}

    def warnings(self, line: ProductLine, witness: Witness) -> Warnings:
        """The warnings of the product ``witness``, resolved again only when what its
        resolution reads changed."""
        key = _inputs(line, witness)
        kept = self._kept.get(witness)
        if kept is not None and kept[1] == key:
            return kept[2]
        found, complete = _resolved(line, witness)
        self._kept.pop(witness, None)
        if complete:
            self._kept[witness] = (line.tsm, key, found)
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


def _inputs(line: ProductLine, witness: Witness) -> tuple:
    """What the resolution of ``witness`` reads: the template but the containers it drops
    whole, the feature model, and the elements it activates, in file order."""
    selected = set(witness)
    package = tsm().package
    touched: set[int] = set()  # the template's declarations the active elements refer into

    def target(value: Any) -> object:
        if value.eClass.ePackage is not package:
            return _named(value)
        declaration = value
        while (owner := declaration.eContainer()) is not None and owner.eContainer() is not None:
            declaration = owner
        touched.add(id(declaration))
        return id(value)

    elements = tuple(
        fingerprint(element, target)
        for element in line.rm.elements
        if (element.feature is not None and element.feature.name in selected)
        == element.activeIfSelected
    )
    return _template(line.tsm, touched), fingerprint(line.fm, target), elements


def _template(system: tsm_types.System, touched: set[int]) -> tuple:
    """The template as a resolution reads it: each declaration (the very element, which
    the editor's next build takes over when an edit leaves it alone), but a container a
    product drops whole: one of optional nodes and stores only, which no other
    declaration and no active element refers into (it is pruned before anything looks
    at the product's architecture, ``tests/resolver/test_dropped_containers.py``).
    Without the editor's declarations, the System itself."""
    built = built_template(system)
    if built is None:
        return (id(system),)
    items = built.declarations.items
    referred = set().union(*(d.refers_to for d in items.values()))
    return built.declarations.own, tuple(
        (key, id(element))
        for key, element in ((k, built.elements[k]) for k in items)
        if not (items[key].droppable and key not in referred and id(element) not in touched)
    )


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
