"""UVL (Universal Variability Language) import and export, as flamapy/uvlparser write it.

Reading is :mod:`spl.dsl.interop.uvl_reader` (the reference grammar, into plain objects);
:func:`read_uvl` and :func:`parse_uvl` turn the result into an ``fm.FeatureModel``
(pyecore) for the rest of the toolchain, :func:`read_uvl_plain` keeps it plain for
analysis (the only form a model of the Arithmetic or Type level takes: the pyecore
model carries the Boolean level). Names that are not .fm identifiers are renamed as
:mod:`spl.dsl.interop.formats` describes and written back unchanged on export.
"""

from __future__ import annotations

import re
from decimal import Decimal
from pathlib import Path
from typing import Any

from spl.core.diagnostics import Diagnostic, Location, ModelError, model_text
from spl.dsl.fm.plain import FeatureModel, to_ecore
from spl.dsl.fm.printer import format_capabilities, format_formula
from spl.dsl.fm.vocabulary import too_deep
from spl.dsl.interop.interchange import (
    CAPABILITY,
    UVL_ATTRIBUTES,
    exported_attributes,
    original_name,
)
from spl.dsl.interop.uvl_lexer import KEYWORDS
from spl.dsl.interop.uvl_reader import parse_uvl_plain
from spl.dsl.interop.uvl_typed import TypedFeatureModel
from spl.dsl.interop.uvl_typed_writer import UvlFile, uvl_id
from spl.dsl.workspace import Workspace, text_of

# Names spelled like a UVL keyword are quoted on export ("abstract" too: older readers
# took it for one, and a quoted name reads the same).
_UVL_KEYWORDS = KEYWORDS | {"abstract"}
# What the UVL grammar (uvl-parser) accepts unquoted; quoted names exclude . " CR LF.
_UVL_PLAIN_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def read_uvl_plain(path: str | Path) -> FeatureModel:
    """Import a UVL file as a plain :class:`fm_plain.FeatureModel` (what analysis needs,
    without building pyecore objects); raise ModelError with every problem."""
    path = Path(path)
    return parse_uvl_plain(model_text(path), str(path), default_name=path.stem)


def read_uvl(
    path: str | Path, workspace: Workspace | None = None, carried_by: str | None = None
) -> Any:
    """Import a UVL file as an ``fm.FeatureModel``; raise ModelError with every problem.
    Read as the editor's ``workspace`` has it, when given. ``carried_by``: see
    :func:`parse_uvl`."""
    path = Path(path)
    return parse_uvl(text_of(path, workspace), str(path), path.stem, carried_by)


def parse_uvl(
    text: str,
    filename: str = "<string>",
    default_name: str = "FeatureModel",
    carried_by: str | None = None,
) -> Any:
    """Import UVL text; ``default_name`` names the model when it has no namespace.

    The pyecore model holds the Boolean level: a model of the Arithmetic or Type level
    gives its tree and Boolean constraints (what ``spl check`` and the editor show), or,
    when it is read for what carries the Boolean level only (``carried_by``: a product
    line), is refused at its first typed part (docs/fm.md). ``spl convert`` reads UVL
    with :mod:`spl.dsl.interop.uvl_export`, which keeps the typed parts."""
    plain = parse_uvl_plain(text, filename, default_name)
    if isinstance(plain, TypedFeatureModel) and carried_by is not None:
        from spl.dsl.interop.uvl_typed_parts import first_typed_part

        where, part = first_typed_part(plain)
        raise ModelError(
            [
                Diagnostic(
                    where,
                    f"{part}: {carried_by} carries the Boolean level of UVL only (spl analyze "
                    "reads the Arithmetic and Type levels, docs/fm.md)",
                )
            ]
        )
    return ecore_of(plain)


def ecore_of(plain: FeatureModel) -> Any:
    """The plain model as pyecore objects; a tree too deep to build is refused, located."""
    try:
        return to_ecore(plain)
    except RecursionError:
        raise ModelError([too_deep(plain.source.file)]) from None


# -- export ---------------------------------------------------------------------------
_UVL_SYMBOLS = {
    "iff": "<=>",
    "implies": "=>",
    "or": "|",
    "and": "&",
    "not": "!",
}


def write_uvl(model: Any, file: UvlFile | None = None) -> str:
    """The model as UVL text (tab-indented, as flamapy writes it).

    ``requires`` becomes ``=>`` and ``A excludes B`` becomes ``A => !B``: UVL has no
    such operators, and the formulas mean the same. ``file``: what a model read from UVL
    holds beyond the Boolean level, and which of its elements this file writes (a
    conversion from UVL, :mod:`spl.dsl.interop.uvl_export`).
    """
    problems: list[Diagnostic] = []
    lines = [f"namespace {file.namespace if file else uvl_id(model.name)}", ""]
    for section, entries in (("include", file.levels), ("imports", file.imports)) if file else ():
        if entries:
            lines.extend([section, *(f"\t{entry}" for entry in entries), ""])
    lines.append("features")
    _write_feature(model.root, 1, lines, problems, file)
    constraints = [c for c in model.constraints if file is None or c.srcFile == file.own]
    if constraints or (file and file.equations):
        lines.append("")
        lines.append("constraints")
        for constraint in constraints:
            formula = _without_requires_excludes(constraint.formula)
            lines.append(
                "\t"
                + format_formula(
                    formula,
                    name_of=lambda f: _uvl_name(f, problems, file),
                    symbols=_UVL_SYMBOLS,
                    right_assoc_implication=False,
                )
            )
        lines.extend(f"\t{equation}" for equation in (file.equations if file else ()))
    if problems:
        raise ModelError(problems)
    return "\n".join(lines) + "\n"


def _uvl_name(feature: Any, problems: list[Diagnostic], file: UvlFile | None = None) -> str:
    if file is not None:  # read from UVL: every name is one UVL writes
        return file.names[feature.name]
    name = original_name(feature)
    if _UVL_PLAIN_NAME.match(name) and name not in _UVL_KEYWORDS:
        return name
    if any(c in name for c in '."\r\n'):
        problems.append(
            Diagnostic(
                _where(feature),
                f"feature name {name!r} cannot be written in UVL (a quoted UVL name holds "
                "no '.', '\"' or line break): rename the feature",
            )
        )
    return f'"{name}"'


def _where(element: Any) -> Location | None:
    if not getattr(element, "srcFile", None):
        return None
    return Location(element.srcFile, element.srcLine or 0, element.srcCol or 0)


def _write_feature(
    feature: Any, depth: int, lines: list[str], problems: list[Diagnostic], file: UvlFile | None
) -> None:
    # an imported model's root, placed: its own file writes the rest of it
    placed = file is not None and feature.srcFile != file.own
    attributes = exported_attributes(feature)
    if file is not None and placed:
        attributes = [a for a in attributes if a.srcFile == file.own]
    entries = []
    if feature.abstract and not placed:
        entries.append("abstract")
    for attribute in attributes:
        value = attribute.value or ""
        if attribute.name == UVL_ATTRIBUTES:  # UVL attributes kept as written
            entries.append(value)
            continue
        if attribute.type.name == "string":
            if "'" in value or "\n" in value or "\r" in value:
                problems.append(
                    Diagnostic(
                        _where(attribute),
                        f"attribute {attribute.name} of {feature.name}: "
                        f"{value!r} cannot be written as a UVL string",
                    )
                )
            value = f"'{value}'"
        elif attribute.type.name == "double":
            value = _uvl_float(value)
        entries.append(f"{uvl_id(attribute.name)} {value}")
    if feature.sharing is not None and not placed:
        entries.append(f"sharing '{feature.sharing.mode.name}'")
    if feature.capabilities and not placed:
        entries.append(f"{CAPABILITY} '{format_capabilities(feature)}'")
    name = _typed_name(feature, file) if file else _uvl_name(feature, problems)
    _write_line(name, entries, depth, lines)
    groups = feature.groups
    if file is not None and placed:
        groups = [group for group in groups if group.srcFile == file.own]
    _write_groups(groups, depth, lines, problems, file)


def _typed_name(feature: Any, file: UvlFile) -> str:
    """The feature's name with its type before it and cardinality after it."""
    text = file.names[feature.name]
    if feature.name in file.types:
        text = f"{file.types[feature.name]} {text}"
    if feature.name in file.cardinalities:
        lower, upper = file.cardinalities[feature.name]
        text += f" cardinality [{lower}..{'*' if upper == -1 else upper}]"
    return text


def _write_line(name: str, entries: list[str], depth: int, lines: list[str]) -> None:
    if entries:
        name += " {" + ", ".join(entries) + "}"
    lines.append("\t" * depth + name)


def _write_groups(
    groups: Any, depth: int, lines: list[str], problems: list[Diagnostic], file: UvlFile | None
) -> None:
    for group in groups:
        kind = group.kind.name
        if kind == "cardinality":
            upper = "*" if group.upper == -1 else str(group.upper)
            keyword = f"[{group.lower}..{upper}]"
        else:
            keyword = kind
        lines.append("\t" * (depth + 1) + keyword)
        for child in group.features:
            _write_feature(child, depth + 2, lines, problems, file)


def _uvl_float(canonical: str) -> str:
    """A double as UVL's FLOAT token (digits, a dot, digits: no exponent)."""
    text = format(Decimal(canonical), "f")
    return text if "." in text else text + ".0"


def _without_requires_excludes(formula: Any) -> Any:
    """A copy of the formula using only and/or/not/implies/iff."""
    from spl.metamodels import fm as fm_metamodel

    F = fm_metamodel()
    kind = formula.eClass.name
    if kind == "FeatureRef":
        return F.FeatureRef(feature=formula.feature)
    if kind == "Not":
        return F.Not(operand=_without_requires_excludes(formula.operand))
    left = _without_requires_excludes(formula.left)
    right = _without_requires_excludes(formula.right)
    if formula.operator == "requires":
        return F.BinaryFormula(operator="implies", left=left, right=right)
    if formula.operator == "excludes":
        return F.BinaryFormula(operator="implies", left=left, right=F.Not(operand=right))
    return F.BinaryFormula(operator=formula.operator, left=left, right=right)
