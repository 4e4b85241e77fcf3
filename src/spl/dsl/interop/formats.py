"""Feature models in any of the three formats.

``load_feature_model`` / ``save_feature_model`` pick the format from the file suffix
(``.fm``, ``.uvl``, FeatureIDE ``.xml``) so the analysis, ``spl convert`` and the
resolution model accept any of them. What the formats' readers and writers share (the
kept original names, the capability attribute) is :mod:`spl.dsl.interop.interchange`'s: the
formats import it, and this module imports the formats when asked for one.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from spl.core.atomic_write import write_atomically
from spl.core.diagnostics import Diagnostic, Location, ModelError, location_of

if TYPE_CHECKING:
    from spl.dsl.workspace import Workspace

FORMATS = {".fm": "FeatureModel (.fm)", ".uvl": "UVL", ".xml": "FeatureIDE XML"}


def load_feature_model(
    path: str | Path, workspace: Workspace | None = None, carried_by: str | None = None
) -> Any:
    """Read a feature model from a .fm, .uvl or FeatureIDE .xml file; a .fm or .uvl as
    the editor's ``workspace`` has it, when given. ``carried_by``: what the model is read
    for when that carries the Boolean level only (a UVL model of another level is then
    refused, located: :func:`spl.dsl.interop.uvl.parse_uvl`)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".fm":
        from spl.dsl.fm.language import parse_file

        return parse_file(path, workspace)
    if suffix == ".uvl":
        from spl.dsl.interop.uvl import read_uvl

        return read_uvl(path, workspace, carried_by)
    if suffix == ".xml":
        from spl.dsl.interop.featureide import read_featureide

        return read_featureide(path)
    raise ModelError([Diagnostic(Location(str(path), 1, 1), unsupported_format_message(path))])


def load_line_feature_model(path: str | Path, workspace: Workspace | None = None) -> Any:
    """A product line's feature model: the Boolean level, which configurations and
    resolution read (a typed UVL model is refused, not read in part)."""
    return load_feature_model(path, workspace, "a product line's feature model")


def load_analysable_model(path: str | Path, typed: bool = False) -> Any:
    """A feature model as analysis needs it: a UVL file stays in plain objects
    (:mod:`spl.dsl.fm.plain`: reading builds no pyecore object, which dominated the time
    on large community models); .fm and FeatureIDE .xml as :func:`load_feature_model`.
    Both kinds give the same encoding (:func:`spl.resolver.analysis.cnf.encode`).

    A UVL model of the Arithmetic or Type level is returned only to a caller that
    analyses it on SMT (``typed``: ``spl analyze``); the SAT analyses (products, diff,
    the configurator) would drop its equations, so for them it is refused, located."""
    path = Path(path)
    if path.suffix.lower() == ".uvl":
        from spl.dsl.interop.uvl import read_uvl_plain
        from spl.dsl.interop.uvl_typed import TypedFeatureModel
        from spl.dsl.interop.uvl_typed_parts import first_typed_part

        model = read_uvl_plain(path)
        if isinstance(model, TypedFeatureModel) and not typed:
            where, part = first_typed_part(model)
            raise ModelError(
                [
                    Diagnostic(
                        where,
                        f"{part}: this command reads the Boolean level of UVL only (spl "
                        "analyze reads the Arithmetic and Type levels, docs/fm.md)",
                    )
                ]
            )
        return model
    return load_feature_model(path)


def render_feature_model(model: Any, suffix: str) -> bytes:
    """The bytes of ``model`` in the format of ``suffix`` (.fm, .uvl or .xml)."""
    suffix = suffix.lower()
    if suffix == ".fm":
        from spl.dsl.fm.printer import print_model

        _refuse_what_fm_refuses(model)
        text = print_model(model)
        _refuse_what_fm_cannot_read_back(model, text)
        return text.encode("utf-8")
    if suffix == ".uvl":
        from spl.dsl.interop.uvl import write_uvl

        return write_uvl(model).encode("utf-8")
    if suffix == ".xml":
        from spl.dsl.interop.featureide_writer import write_featureide

        return write_featureide(model)
    raise ValueError(f"no feature-model format for {suffix!r}")


def _refuse_what_fm_refuses(model: Any) -> None:
    """A group asking for more features than it has (UVL reads ``[2]`` over one child;
    the model is void) would be written as a .fm file the .fm reader refuses: say so."""
    from spl.dsl.fm.language import all_features

    problems = [
        Diagnostic(
            location_of(group) or location_of(feature),
            f"feature {feature.name}: its group [{group.lower}..{_upper(group.upper)}] asks for "
            f"more features than its {len(group.features)}, which the .fm language refuses (no "
            "product could choose that many: the model is void)",
        )
        for feature in all_features(model)
        for group in feature.groups
        if group.kind.name == "cardinality" and group.lower > len(group.features)
    ]
    if problems:
        raise ModelError(problems)


def _refuse_what_fm_cannot_read_back(model: Any, text: str) -> None:
    """UVL's ``A => B => C`` is ``(A => B) => C``, .fm's is ``A => (B => C)``: a long UVL
    chain is written with one parenthesis per implication, and the .fm reader follows a
    few dozen. Text nested beyond what the fast reader takes is read back, and refused,
    at each constraint nested that deep, when the reader refuses it."""
    from spl.dsl.fm import language as fm, reader as fm_reader
    from spl.dsl.fm.printer import format_formula

    if _parentheses(text) <= fm_reader.MAX_DEPTH:
        return
    try:
        fm.parse_text(text, "converted.fm")
    except ModelError as exc:
        reason = exc.diagnostics[0].message
        deep = [
            (constraint, depth)
            for constraint in model.constraints
            if (depth := _parentheses(format_formula(constraint.formula))) > fm_reader.MAX_DEPTH
        ]
        raise ModelError(
            [
                Diagnostic(
                    location_of(constraint),
                    f"this constraint is written with {depth} nested parentheses in .fm (an "
                    f"implication chain associates the other way there), which the .fm reader "
                    f"refuses ({reason}): split it into several constraints",
                )
                for constraint, depth in deep
            ]
            or exc.diagnostics
        ) from None


def _parentheses(text: str) -> int:
    depth = deepest = 0
    for character in text:
        if character == "(":
            depth += 1
            deepest = max(deepest, depth)
        elif character == ")":
            depth -= 1
    return deepest


def _upper(bound: int) -> str:
    return "*" if bound == -1 else str(bound)


def converted_files(source: Path, target: Path) -> tuple[str, dict[Path, tuple[Path, bytes]]]:
    """What ``spl convert SOURCE TARGET`` writes: the model's summary line and each
    output path -> (the input file it converts, its bytes), ``target`` first, all
    rendered before anything is written.

    UVL to UVL keeps every language level and a composed model's submodels (written at
    their import paths beside ``target``); to .fm and FeatureIDE XML, a UVL model of the
    Arithmetic or Type level is refused at its first typed part (docs/fm.md, "Conversion:
    what each target keeps")."""
    if source.suffix.lower() != ".uvl":
        from spl.dsl.fm.language import summary

        model = load_feature_model(source)
        return summary(model), {target: (source, render_feature_model(model, target.suffix))}
    from spl.dsl.interop.uvl import ecore_of, read_uvl_plain
    from spl.dsl.interop.uvl_export import refuse_uncarried, uvl_conversion
    from spl.dsl.interop.uvl_summary import summary as typed_summary

    if target.suffix.lower() == ".uvl":
        plain, texts = uvl_conversion(source, target)
        files = {path: (read, text.encode("utf-8")) for path, (read, text) in texts.items()}
        return typed_summary(plain), files
    plain = read_uvl_plain(source)
    refuse_uncarried(plain, FORMATS[target.suffix.lower()])
    data = render_feature_model(ecore_of(plain), target.suffix)
    return typed_summary(plain), {target: (source, data)}


def save_feature_model(model: Any, path: str | Path) -> None:
    """Write ``model`` to ``path`` in the format its suffix names, atomically.

    The text is rendered completely before anything is written, and written to a
    temporary file renamed over the target, so a failed export never leaves half a file.
    """
    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        raise ValueError(unsupported_format_message(path))
    write_atomically(path, render_feature_model(model, path.suffix))


def unsupported_format_message(path: Path) -> str:
    known = ", ".join(sorted(FORMATS))
    return f"{path}: unsupported feature-model format {path.suffix or '(none)'!r} (use {known})"
