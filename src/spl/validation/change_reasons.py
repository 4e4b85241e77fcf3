"""Why a product's bundle file changed between two versions of its line: one line per
file, naming the element and its place in the new models, in the words of ``spl
explain`` (docs/evolution.md, "Why a file changed").

What changed for a product is found where the resolver records it, never guessed from
the files: the decisions of its trace that only one version took (compared without
their locations, which move with any edit above them); the template elements the
product holds whose definitions differ (:func:`template_changes`, once for the pair
of versions); the features whose attribute values or selection differ. Each is
explained by the caller's ``explain`` (``spl explain``'s own function, handed in so
this layer does not depend on the command line) in the new version's product. A file
is given the first of them whose name its changed lines mention, else the product's
first: ``manifest.json`` lists every file's hash, so it changes with any of them.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from spl.core.diagnostics import location_of
from spl.core.emf_compare import differences
from spl.resolver.resolution.explanation import named_elements

if TYPE_CHECKING:
    from spl.metamodels import tsm_types
    from spl.pipeline import Derivation
    from spl.resolver.resolution.engine import Resolution
    from spl.resolver.resolution.product_line import ProductLine
    from spl.resolver.resolution.trace import TraceEntry

# spl explain's lines about a name in a product: (line, resolution, name) -> lines or None
Explain = Callable[["ProductLine", "Resolution", str], "list[str] | None"]

LOCATED = re.compile(r" \([^()]*:\d+:\d+\)")  # a "(file:line:col)" a trace reason names


@dataclass(frozen=True)
class Cause:
    """One thing that differs for the product: the element it is about, and the reason
    said of it."""

    subject: str
    reason: str


@dataclass(frozen=True)
class TemplateEdit:
    """What the edit did to the template, found once for the pair of versions:
    ``changed`` (:func:`template_changes`) and where ``new`` writes each element."""

    changed: dict[str, str]
    written: dict[str, str]

    @classmethod
    def of(cls, old: tsm_types.System, new: tsm_types.System) -> TemplateEdit:
        written = {n.name: str(location_of(n.element) or "") for n in named_elements(new)}
        return cls(template_changes(old, new), written)


def template_changes(old: tsm_types.System, new: tsm_types.System) -> dict[str, str]:
    """The template elements of ``new`` that ``old`` lacks or defines otherwise (source
    locations aside), the innermost of each nesting (a parameter rather than its node),
    by qualified name, each with where ``new`` writes it."""
    before = {named.name: named.element for named in named_elements(old)}
    flagged = [
        named
        for named in named_elements(new)
        if named.name not in before or any(differences(before[named.name], named.element))
    ]
    holders = {id(h) for named in flagged for h in _holders(named.element)}
    return {
        named.name: str(location_of(named.element) or "")
        for named in flagged
        if id(named.element) not in holders
    }


def _holders(element: tsm_types.NamedElement) -> Iterator[object]:
    owner = element.eContainer()
    while owner is not None:
        yield owner
        owner = owner.eContainer()


def causes(
    old: Derivation,
    new: Derivation,
    new_line: ProductLine,
    template: TemplateEdit,
    explain: Explain,
) -> list[Cause]:
    """What differs for one product between its two derivations, in explain's words:
    the new version's decisions the old did not take, then the template elements of the
    product defined anew, then the decisions only the old took, then features."""
    before, after = old.resolution, new.resolution
    old_keys = {_key(e) for e in before.trace.entries}
    new_keys = {_key(e) for e in after.trace.entries}
    found: dict[str, Cause] = {}
    for entry in after.trace.entries:
        if _key(entry) not in old_keys:
            found.setdefault(entry.subject, Cause(entry.subject, str(entry)))
    present = {named.name for named in named_elements(after.product.system)}
    for name, where in template.changed.items():
        if name in present and name not in found:
            found[name] = Cause(name, _explained(new_line, after, name, explain, where))
    for entry in before.trace.entries:
        if _key(entry) not in new_keys and entry.subject not in found:
            # the decision is gone: the element as it stands now, where the template
            # writes it, and what was decided before
            lines = explain(new_line, after, entry.subject) or [
                f"{entry.subject}: not in this product"
            ]
            where = template.written.get(entry.subject, "")
            said = f"{lines[0]} ({where})" if where else lines[0]
            was = f"{entry.decision}: {LOCATED.sub('', entry.reason)}"
            found[entry.subject] = Cause(entry.subject, f"{said}; was {was}")
    for feature in _features(before, after):
        if feature not in found:
            found[feature] = Cause(feature, _explained(new_line, after, feature, explain, ""))
    return list(found.values())


def _key(entry: TraceEntry) -> tuple[str, str, str]:
    return entry.subject, entry.decision, LOCATED.sub("", entry.reason)


def _features(before: Resolution, after: Resolution) -> list[str]:
    """Features selected in one product only, then those whose attribute values differ."""
    selected = sorted(set(before.product.features) ^ set(after.product.features))
    attributes = before.product.attributes, after.product.attributes
    keys = sorted(
        k for k in attributes[0].keys() | attributes[1].keys()
        if attributes[0].get(k) != attributes[1].get(k)
    )  # fmt: skip
    return list(dict.fromkeys([*selected, *(k.partition(".")[0] for k in keys)]))


def _explained(
    line: ProductLine, resolution: Resolution, name: str, explain: Explain, where: str
) -> str:
    """One line of what ``spl explain`` says of ``name``: its standing, then its first
    line naming a place in the models, else ``where`` (its place in the template)."""
    lines = explain(line, resolution, name) or [f"{name}: not in this product"]
    head = lines[0]
    located = next((text.strip() for text in lines[1:] if LOCATED.search(text)), None)
    if located is not None:
        return f"{head}; {located}"
    return f"{head} ({where})" if where else head


def file_reasons(
    old_files: dict[str, bytes], new_files: dict[str, bytes], paths: list[str], found: list[Cause]
) -> dict[str, str]:
    """Each changed path's reason: the first cause its changed lines name (module
    docstring), else the product's first cause."""
    fallback = found[0].reason if found else "the product's derivation differs"
    reasons = {}
    for path in paths:
        changed = _changed_lines(old_files.get(path, b""), new_files.get(path, b""))
        reasons[path] = next((c.reason for c in found if _mentions(changed, c.subject)), fallback)
    return reasons


def _changed_lines(before: bytes, after: bytes) -> str:
    """The lines only one version of the file has, lower-cased, one text."""
    old = set(before.decode("utf-8", "replace").splitlines())
    new = set(after.decode("utf-8", "replace").splitlines())
    return "\n".join(sorted(old ^ new)).lower()


def _mentions(text: str, subject: str) -> bool:
    """Whether the changed lines name the subject's own name (its last part: a
    parameter, an interface, a topic as they are written in the files)."""
    own = subject.rpartition(".")[2].lower()
    return (
        bool(own) and re.search(rf"(?<![a-z0-9_]){re.escape(own)}(?![a-z0-9_])", text) is not None
    )
