"""The warnings of the witness products the line checks resolve, remembered from one check
of a line to the next (the editor's, after every change: its workspace's memory of the
line, :class:`spl.dsl.workspace.LineMemory`).

Why: the dataflow check confirms each unfed input by resolving a witness product
(:mod:`.dataflow`), and on a 10,000-node line that one resolution is half a second of
every check, while most edits change nothing it reads: a new resolution element for a
feature the witness leaves out, a node no product keeps, lines added above the rest.

A resolution reads the template, the feature model, and the resolution elements the
product activates, in file order (:mod:`spl.resolver.resolution.engine`); nothing else. So a
remembered resolution is reused when those are equal in content: the template's
declarations by their prints (:mod:`spl.dsl.tsm.declarations`, the editor's build of
the .tsm has them), but for those a product drops before anything looks at its
architecture (an optional node or store, or a container of them only, that nothing
else refers into and no active element names: ``tests/resolver/test_dropped_containers.py``),
and the feature model and the active elements with their source locations, since
messages cite them (:func:`spl.core.emf.fingerprint`). A declaration's print counts its lines
from its first, so a remembered resolution also serves a template whose declarations
moved: its warnings move with the declaration each is in, and one in none of them, or
one whose message cites the template, moves nowhere and the product is resolved again.
Only a resolution that succeeded without completing the selection is remembered: a
completed one activates elements of features the witness does not name, and a failed
one says nothing of which elements it read.
"""

from __future__ import annotations

import bisect
import dataclasses
from typing import Any

from spl.core.cyclic_gc import collect_young, without_cyclic_gc
from spl.core.diagnostics import Diagnostic, ModelError
from spl.core.emf import fingerprint
from spl.dsl.tsm.declaration_paths import Key, path_of
from spl.dsl.tsm.declarations import BuiltTemplate, Declarations
from spl.dsl.workspace import LineMemory, Workspace
from spl.metamodels import tsm
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.product_selection import selection_from_list

Witness = tuple[str, ...]
Warnings = tuple[Diagnostic, ...]
Lines = dict[Key, tuple[int, int]]  # the first and last line of each declaration read


@dataclasses.dataclass(frozen=True)
class _Remembered:
    key: tuple
    lines: Lines
    warnings: Warnings


class WitnessResolutions:
    """The last resolutions of witness products of one line, by witness."""

    KEPT = 16  # witnesses remembered

    def __init__(self) -> None:
        self._kept: dict[Witness, _Remembered] = {}

    def warnings(
        self, line: ProductLine, witness: Witness, built: BuiltTemplate | None
    ) -> Warnings:
        """The warnings of the product ``witness``, resolved again only when what its
        resolution reads changed; ``built``: the line's template as the editor built it."""
        if built is None:  # not the editor's template: no declarations to compare
            return _resolved(line, witness)[0]
        key, lines = _inputs(line, built.declarations, witness)
        kept = self._kept.get(witness)
        if kept is not None and kept.key == key:
            moved = moved_findings(kept.lines, kept.warnings, lines, line.tsm.srcFile)
            if moved is not None:
                return moved
        found, complete = _resolved(line, witness)
        self._kept.pop(witness, None)
        if complete:
            self._kept[witness] = _Remembered(key, lines, found)
            while len(self._kept) > self.KEPT:
                del self._kept[next(iter(self._kept))]
        return found


def witness_warnings(
    line: ProductLine, witness: Witness, workspace: Workspace | None = None
) -> Warnings:
    """The warnings of the product ``witness`` (none when it does not resolve, which
    resolve, validate and the other checks report); in an editor's ``workspace`` that
    remembers the line, resolved again only when what the resolution reads changed."""
    editing = line_in_editor(line, workspace)
    if editing is None:
        return _resolved(line, witness)[0]
    memory, built = editing
    return memory.of(WitnessResolutions).warnings(line, witness, built)


def line_in_editor(
    line: ProductLine, workspace: Workspace | None
) -> tuple[LineMemory, BuiltTemplate | None] | None:
    """The editor's memory of ``line``, and the line's template as the editor built it
    (None for another build); None outside an editor that remembers the line."""
    memory = workspace.line_memory(line.directory) if workspace is not None else None
    if memory is None or workspace is None or workspace.models is None:
        return None
    return memory, workspace.models.built_template(line.tsm)


def _resolved(line: ProductLine, witness: Witness) -> tuple[Warnings, bool]:
    """The product's warnings, and whether it resolved without completing the selection."""
    from spl.resolver.resolution.engine import resolve  # the engine imports the line checks' kin

    # paused until the product is released and its remains collected: resolve() alone
    # would resume collection over the live product, and a caller not paused already
    # (spl check and the editor are) paid a young collection over all of it
    with without_cyclic_gc("left"):
        try:
            resolution = resolve(line, selection_from_list(",".join(witness)))
        except ModelError:
            return (), False
        found = resolution.product.warnings, not resolution.completion.added
        resolution.release()  # nothing reads the product again: its model goes now
        del resolution
        collect_young()  # and what it built around the model, with the next product's room
    return found


def _inputs(line: ProductLine, found: Declarations, witness: Witness) -> tuple[tuple, Lines]:
    """What the resolution of ``witness`` reads: the template's declarations but those it
    drops, the feature model, and the elements it activates, in file order; and the
    lines of the declarations read."""
    selected = set(witness)
    active = [
        element
        for element in line.rm.elements
        if (element.feature is not None and element.feature.name in selected)
        == element.activeIfSelected
    ]
    elements, touched = _element_prints(active)
    return template_reads(line.fm, found, _resolution_reads(found, touched), elements)


def _element_prints(elements: list[Any]) -> tuple[tuple, set[Key]]:
    """The prints of resolution ``elements`` (their places included: messages cite
    them), and the template's declarations they refer into."""
    package = tsm().package
    touched: set[Key] = set()

    def target(value: Any) -> object:
        if value.eClass.ePackage is not package:
            return _named(value)
        path = path_of(value)
        touched.add(path[0])
        return path

    return tuple(fingerprint(element, target) for element in elements), touched


def template_reads(
    fm: Any, found: Declarations, read: list[Key], elements: tuple
) -> tuple[tuple, Lines]:
    """A key of what a computation reads: the template's declarations ``read`` (by their
    prints), the feature model and the resolution ``elements``' prints; and the lines
    of the declarations read, to move what it found with them (:func:`moved_findings`)."""
    name, file, first, column = found.own  # the System's line moves as the rest does
    template = ((name, file, column), tuple((k, found.items[k].print) for k in read))
    lines = {k: found.items[k].lines for k in read}
    lines[()] = (first, first)
    return (template, fingerprint(fm, _named), elements), lines


def _resolution_reads(found: Declarations, touched: set[Key]) -> list[Key]:
    """The declarations a resolution reads: not an optional node or store, nor a
    container of only those, that no other declaration (outside the container) and no
    active element refers into: a product prunes them before anything looks at its
    architecture."""
    items = found.items
    referred, referred_containers = referred_declarations(found)
    kept = referred | touched
    kept_containers = referred_containers | {k[:2] for k in touched}

    def dropped(key: Key) -> bool:
        if key[0] == "containers" and items[key[:2]].droppable and key[:2] not in kept_containers:
            return True
        return len(key) == 4 and items[key].droppable and key not in kept

    return [k for k in items if not dropped(k)]


def referred_declarations(found: Declarations) -> tuple[set[Key], set[Key]]:
    """The declarations another declaration refers into, and the containers referred
    into from outside them."""
    referred: set[Key] = set()
    referred_containers: set[Key] = set()
    for key, declaration in found.items.items():
        for target in declaration.refers_to:
            referred.add(target)
            if target[:2] != key[:2]:
                referred_containers.add(target[:2])
    return referred, referred_containers


def moved_findings(before: Lines, findings: Warnings, lines: Lines, file: str) -> Warnings | None:
    """``findings`` made on a template whose declarations read were where ``before``
    says, in one whose same declarations (equal in content, so each moved whole) are
    where ``lines`` says: each finding located in the template moved with the
    declaration it is in; None when one is in none of them, or one's message cites a
    place in the template that moved."""
    if before == lines:
        return findings
    spans = sorted((first, last, lines[k][0] - first) for k, (first, last) in before.items())
    regions: list[list[int]] = []  # [first, last, moved by] of overlapping declarations
    for first, last, moved in spans:
        if regions and first <= regions[-1][1]:
            if moved != regions[-1][2]:
                return None
            regions[-1][1] = max(regions[-1][1], last)
        else:
            regions.append([first, last, moved])
    starts = [r[0] for r in regions]
    found = []
    for warning in findings:
        where = warning.location
        if file in warning.message:
            return None
        if where is None or where.file != file:
            found.append(warning)
            continue
        at = bisect.bisect_right(starts, where.line) - 1
        if at < 0 or where.line > regions[at][1]:
            return None
        moved_to = dataclasses.replace(where, line=where.line + regions[at][2])
        found.append(dataclasses.replace(warning, location=moved_to))
    return tuple(found)


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
