"""``spl diff OLD_DIR NEW_DIR``: what an edit of a product line did to its products
(docs/evolution.md, "Comparing two versions of a line").

The products compared are those ``spl validate`` would validate in each version (its
plan: the listed ``products/*.yaml``, plus every product or a t-wise sample), each
looked for in the other version as the same product (:mod:`spl.validation.bundle_changes`).
A product both versions derive is *changed* when a bundle file differs, else
*unchanged*; one only the new version derives is *added*, one only the old derives
*removed* (with why the new version refuses it). Each product of each version is
derived once, and each version's models were loaded once by the caller.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from spl.validation.bundle_changes import (
    Derived,
    Version,
    changed_paths,
    derive,
    product_name,
    whole_product,
)
from spl.validation.change_reasons import Explain, TemplateEdit, causes, file_reasons
from spl.validation.line import LoadedLine, ProductCase, plan_cases

if TYPE_CHECKING:
    from spl.generators.bundle.inputs import BundleMemo
    from spl.generators.bundle.options import BundleOptions

# A product as both versions know it: ("listed", file name) or ("product", its features).
Identity = tuple[str, Any]


@dataclass
class LineChanges:
    """The products of the comparison, each ``{"product", "features"}`` (and ``files``
    for a changed one, ``reason`` for a removed one), in the order of the plans."""

    added: list[dict[str, Any]] = field(default_factory=list)
    removed: list[dict[str, Any]] = field(default_factory=list)
    changed: list[dict[str, Any]] = field(default_factory=list)
    unchanged: int = 0

    def as_json(self) -> dict[str, Any]:
        return {
            "added": self.added,
            "removed": self.removed,
            "unchanged": self.unchanged,
            "changed": self.changed,
        }


@dataclass
class _Side:
    version: Version
    derived: dict[Identity, Derived] = field(default_factory=dict)


def compare_lines(
    old: Version,
    new: Version,
    mode: str,
    t: int,
    explain: Explain,
    options: BundleOptions,
    memo: BundleMemo | None = None,
) -> LineChanges:
    """Every planned product of both versions compared (module docstring); ``mode`` and
    ``t`` as ``spl validate`` plans (``listed``, ``all``, ``sample``); ``explain`` says
    a changed file's reason."""
    sides = _Side(old), _Side(new)
    planned: dict[Identity, ProductCase] = {}
    for index in (1, 0):  # the new version's products first, in its plan's order
        version = sides[index].version
        loaded = LoadedLine(version.directory, version.line.name, version.line)
        for case in plan_cases([loaded], mode, t):
            planned.setdefault(_identity(version, case), case)
    template = TemplateEdit.of(old.line.tsm, new.line.tsm)
    result = LineChanges()
    for identity, case in planned.items():
        features = identity[1] if identity[0] == "product" else None
        before, after = (_derived(side, identity, case, features, options, memo) for side in sides)
        if before.derivation is None and after.derivation is None:
            continue  # neither version derives it: no product of the line to compare
        if before.derivation is None:
            result.added.append(_named(new, case, after))
        elif after.derivation is None:
            entry = _named(old, case, before)
            result.removed.append({**entry, "reason": after.problems[0]})
        else:
            paths = changed_paths(before, after, old.directory, new.directory)
            if not paths:
                result.unchanged += 1
            else:
                entry = _named(new, case, after)
                found = causes(before.derivation, after.derivation, new.line, template, explain)
                files_before = before.derivation.bundle.files
                files_after = after.derivation.bundle.files
                reasons = file_reasons(files_before, files_after, paths, found)
                entry["files"] = [{"path": p, "reason": reasons[p]} for p in paths]
                result.changed.append(entry)
    return result


def _identity(version: Version, case: ProductCase) -> Identity:
    if case.selection_file is not None:
        return "listed", case.selection_file.name
    return "product", whole_product(version.line, case.features)


def _derived(
    side: _Side,
    identity: Identity,
    case: ProductCase,
    features: frozenset[str] | None,
    options: BundleOptions,
    memo: BundleMemo | None,
) -> Derived:
    """The product in this version, derived once."""
    if identity not in side.derived:
        side.derived[identity] = derive(side.version, case, features, options, memo)
    return side.derived[identity]


def _named(version: Version, case: ProductCase, derived: Derived) -> dict[str, Any]:
    """``{"product", "features"}``: the name ``spl validate`` gives the case in this
    version (a generated product's, from this version's own non-core features), and
    the features as ``spl products`` prints them."""
    features = ",".join(product_name(version.line, derived.features))
    return {
        "product": case.name if case.selection_file is not None else features,
        "features": features,
    }
