"""Whether a product's bundle changed between two versions of its line
(docs/evolution.md, "Comparing two versions of a line").

A product of the new version is looked for in the old one as the same product: a listed
product by its selection file of the same name in the old folder's ``products/``; a
generated one by its whole set of selected features, given to the old version as that
version's own non-core features (what ``spl products`` prints and ``spl validate``
derives), and found only when the old version completes them to the same set. Both
bundles are generated in memory by :func:`spl.pipeline.derive` and compared file by file.

The two versions are one line in two folders, and the folder is no change: the only
place a bundle names it is ``manifest.json``'s warnings, whose locations name the model
files as they were read. The old bundle's manifest is compared with those locations
moved into the new folder (:func:`relocated`), so a warning that stands where it stood
is no change, and one that moved in its file (another line) is one.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from spl import pipeline
from spl.core.diagnostics import Diagnostic, Location, ModelError

if TYPE_CHECKING:
    from spl.generators.bundle.inputs import BundleMemo
    from spl.generators.bundle.options import BundleOptions
    from spl.resolver.resolution.product_line import ProductLine
    from spl.resolver.resolution.product_selection import ProductSelection
    from spl.validation.line import ProductCase

MANIFEST = "manifest.json"


@dataclass(frozen=True)
class Version:
    """One version of a line: the folder its models were read from, and the line."""

    directory: Path
    line: ProductLine


@dataclass(frozen=True)
class Derived:
    """A product derived from one version, or the errors that refused it."""

    derivation: pipeline.Derivation | None
    problems: tuple[str, ...] = ()

    @property
    def features(self) -> frozenset[str]:
        if self.derivation is None:
            return frozenset()
        return frozenset(self.derivation.resolution.product.features)


def whole_product(line: ProductLine, key: tuple[str, ...]) -> frozenset[str]:
    """The features a generated product selects: its non-core ``key`` and the core."""
    return frozenset(key) | line.formula.backbone()[0]


def product_name(line: ProductLine, features: frozenset[str]) -> tuple[str, ...]:
    """A product's non-core features in feature-model order, as ``spl products`` prints
    them (the root alone for the product of core features only)."""
    from spl.resolver.analysis.sampling import product_key

    return tuple(product_key(line.formula, features)) or (line.formula.cnf.names[0],)


def generated_selection(line: ProductLine, features: frozenset[str]) -> ProductSelection | None:
    """The selection ``spl validate`` derives the product of ``features`` from in
    ``line``; None when ``line``'s feature model lacks one of them."""
    from spl.resolver.resolution.product_selection import selection_from_list

    if not features <= set(line.formula.cnf.names):
        return None
    key = product_name(line, features)
    return selection_from_list(",".join(key), name="_".join(key))


def derive(
    version: Version,
    case: ProductCase,
    features: frozenset[str] | None,
    options: BundleOptions,
    memo: BundleMemo | None,
) -> Derived:
    """The product of ``case`` in ``version``: a listed product by its file name in the
    version's ``products/``, a generated one by its whole feature set ``features``
    (which the version must complete to the same set)."""
    from spl.resolver.resolution.product_selection import load_selection_file

    try:
        if case.selection_file is not None:
            path = version.directory / "products" / case.selection_file.name
            if not path.is_file():
                return Derived(None, (f"{path}: no such selection file",))
            selection = load_selection_file(path)
        else:
            assert features is not None
            found = generated_selection(version.line, features)
            if found is None:
                return Derived(None, ("not a product of this version's feature model",))
            selection = found
        derived = Derived(pipeline.derive(version.line, selection, options, memo))
    except ModelError as exc:
        errors = [d for d in exc.diagnostics if d.severity == "error"] or exc.diagnostics
        return Derived(None, tuple(str(d) for d in errors))
    if features is not None and derived.features != features:
        return Derived(None, ("not a product of this version's feature model",))
    return derived


def changed_paths(old: Derived, new: Derived, old_folder: Path, new_folder: Path) -> list[str]:
    """The bundle paths whose bytes differ (a path only one bundle has included), the
    folder the versions were read from left out (module docstring)."""
    assert old.derivation is not None and new.derivation is not None
    before, after = old.derivation.bundle.files, new.derivation.bundle.files
    changed = [p for p in sorted(before.keys() | after.keys()) if before.get(p) != after.get(p)]
    if MANIFEST in changed and MANIFEST in before and MANIFEST in after:
        warnings = old.derivation.resolution.product.warnings
        moved = [str(relocated(w, old_folder, new_folder)) for w in warnings]
        if _manifest(before[MANIFEST], moved) == _manifest(after[MANIFEST], None):
            changed.remove(MANIFEST)
    return changed


def relocated(warning: Diagnostic, old_folder: Path, new_folder: Path) -> Diagnostic:
    """``warning`` with its location in ``new_folder`` when it is in ``old_folder``."""
    where = warning.location
    if where is None:
        return warning
    inside = os.path.relpath(os.path.abspath(where.file), os.path.abspath(old_folder))
    if inside.startswith(os.pardir):
        return warning
    return replace(warning, location=Location(str(new_folder / inside), where.line, where.col))


def _manifest(data: bytes, warnings: list[str] | None) -> object:
    document = json.loads(data)
    if warnings is not None and isinstance(document, dict):
        document["warnings"] = warnings
    return document


def unchanged(
    base: Version,
    new: Version,
    case: ProductCase,
    derivation: pipeline.Derivation,
    options: BundleOptions,
    memo: BundleMemo | None,
) -> bool:
    """Whether the old version ``base`` derives the same bundle for ``case`` as
    ``derivation`` (the new version's): ``spl validate --changed-from``'s skip."""
    features = None
    if case.selection_file is None:
        features = frozenset(derivation.resolution.product.features)
    old = derive(base, case, features, options, memo)
    if old.derivation is None:
        return False
    return not changed_paths(old, Derived(derivation), base.directory, new.directory)
