"""``spl convert`` of a UVL model: what each target keeps of it (docs/fm.md, "Conversion:
what each target keeps").

To UVL the model is kept whole, every language level: the tree, the Boolean constraints
and the typed parts (:mod:`spl.dsl.interop.uvl_typed_writer`), and a composed model keeps
its submodels: the converted file imports them as the input does, and each imported
model is written, converted the same way, at its import path beside the output. A
dotted name such as ``Size.Size`` is a UVL name only through an import, so one composed
file could not keep the names as written.

.fm and FeatureIDE XML carry the Boolean level (tree, Boolean constraints, attributes
with fixed values): a typed model is refused at the first part, in file order, the
target cannot carry, rather than written without it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from spl.core.diagnostics import Diagnostic, Location, ModelError
from spl.dsl.fm.plain import FeatureModel
from spl.dsl.interop.interchange import written_names
from spl.dsl.interop.uvl import ecore_of, read_uvl_plain, write_uvl
from spl.dsl.interop.uvl_typed import TypedFeatureModel, features_of
from spl.dsl.interop.uvl_typed_parts import dotted_name, first_typed_part
from spl.dsl.interop.uvl_typed_writer import (
    UvlFile,
    add_typed_parts,
    uvl_id,
)


def uvl_conversion(source: Path, target: Path) -> tuple[FeatureModel, dict[Path, tuple[Path, str]]]:
    """The model read from ``source`` and the files converting it to UVL at ``target``
    writes: each output path -> (the file it converts, its text); ``target`` first, then
    the submodels at their import paths beside it."""
    files: dict[Path, tuple[Path, str]] = {}
    plain = read_uvl_plain(source)
    _convert(plain, Path(source), target, files)
    return plain, files


def _convert(
    plain: FeatureModel, source: Path, target: Path, files: dict[Path, tuple[Path, str]]
) -> None:
    model = ecore_of(plain)
    own = plain.source.file
    written = written_names(model)
    file = UvlFile(own=own, names=_uvl_names(model, own, written), namespace=_namespace(plain))
    placed = _placements(model, own)
    submodels: list[tuple[FeatureModel, Path]] = []
    for root in placed:
        sub_source = Path(root.srcFile)
        sub = read_uvl_plain(sub_source)
        if sub.root is None or sub.root.source.file != sub.source.file:
            raise ModelError(
                [
                    Diagnostic(
                        Location(root.srcFile, root.srcLine, root.srcCol),
                        "the root of this imported model is itself an imported model's root: "
                        "spl convert keeps a composition whose submodels each have a root of "
                        "their own",
                    )
                ]
            )
        relative = sub_source.relative_to(source.parent)  # imports resolve beside the file
        path = [*relative.parent.parts, relative.stem]
        sub_root = written_names(sub)[sub.root.name]
        alias = written[root.name][: -len(sub_root) - 1]
        entry = ".".join(uvl_id(part) for part in path)
        if alias != ".".join(path):
            entry += f" as {dotted_name(alias)}"
        file.imports.append(entry)
        submodels.append((sub, relative))
    if isinstance(plain, TypedFeatureModel):
        by_name = {feature.name: feature for feature in features_of(plain)}

        def owned(name: str) -> bool:
            return by_name[name].source.file == own

        file.types = {name: kind for name, kind in plain.types.items() if owned(name)}
        file.cardinalities = {
            name: (lower, upper)
            for name, (lower, upper, _) in plain.cardinalities.items()
            if owned(name)
        }
        for root, (sub, _) in zip(placed, submodels, strict=True):
            _placement_parts(file, plain, root.name, sub)
        add_typed_parts(file, plain, owned)
    files[target] = (source, write_uvl(model, file))
    for sub, relative in submodels:
        _convert(sub, Path(sub.source.file), target.parent / relative, files)


def _placement_parts(file: UvlFile, plain: TypedFeatureModel, name: str, sub: FeatureModel) -> None:
    """A type or cardinality the importing file writes on an imported root (``Integer
    sub.S``): the composed model has it and the submodel alone does not."""
    if sub.root is None:  # refused where the submodel is read
        return
    types = sub.types if isinstance(sub, TypedFeatureModel) else {}
    cardinalities = sub.cardinalities if isinstance(sub, TypedFeatureModel) else {}
    if name in plain.types and sub.root.name not in types:
        file.types[name] = plain.types[name]
    if name in plain.cardinalities and sub.root.name not in cardinalities:
        file.cardinalities[name] = plain.cardinalities[name][:2]


def _namespace(plain: FeatureModel) -> str:
    """The namespace as the file writes it (a file stem, without one), or as an
    identifier where UVL cannot quote a part of it (a stem holding '"' or '..')."""
    parts = plain.written_name.split(".")
    if all(part and not any(c in part for c in '"\r\n') for part in parts):
        return dotted_name(plain.written_name)
    return uvl_id(plain.name)


def _uvl_names(model: Any, own: str, written: dict[str, str]) -> dict[str, str]:
    """Each feature's identifier -> its name as UVL text: quoted where UVL needs it, and
    an imported feature's ``alias.Name`` as a reference to it."""
    names: dict[str, str] = {}
    stack = [model.root]
    while stack:
        feature = stack.pop()
        name = written[feature.name]
        names[feature.name] = uvl_id(name) if feature.srcFile == own else dotted_name(name)
        stack.extend(child for group in feature.groups for child in group.features)
    return names


def _placements(model: Any, own: str) -> list[Any]:
    """The imported models' roots the file's tree places, in file order."""
    found: list[Any] = []
    stack = [model.root]
    while stack:
        feature = stack.pop()
        if feature.srcFile != own:
            found.append(feature)
            children = [c for g in feature.groups if g.srcFile == own for c in g.features]
        else:
            children = [c for g in feature.groups for c in g.features]
        stack.extend(reversed(children))
    return found


def refuse_uncarried(plain: FeatureModel, target: str) -> None:
    """Raise ModelError at the first typed part of ``plain`` (file order, an imported
    model's parts where its placement stands), naming it and the ``target`` format."""
    if not isinstance(plain, TypedFeatureModel):
        return
    where, part = first_typed_part(plain)
    raise ModelError(
        [
            Diagnostic(
                where,
                f"{part}: spl convert to {target} cannot carry it ({target} holds the Boolean "
                "level: the tree, Boolean constraints and attributes with fixed values); "
                "convert to UVL to keep every level (docs/fm.md)",
            )
        ]
    )
