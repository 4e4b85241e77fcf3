"""The one place the order of spl's work is written down (docs/index.md, "Pipeline"):

    load the line (parse .rm, .tsm, .fm; build the feature formula)
      -> check the selection and resolve it (M2M: the resolved architecture)
      -> emit the bundle (M2T: every target's files, in memory)
      -> validate or write it.

The commands (`resolve`, `validate`, `check`, `render`, `explain`), the validation
workers, the smoke rehearsal and the language server call these functions instead of
spelling the sequence out again, so a new step (a new target, a new check) is added
here once. Each step lives in its own layer (spl.dsl, spl.resolver, spl.generators);
this module only orders them.
"""

from __future__ import annotations

import contextlib
import importlib
import json
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from spl.core.diagnostics import Diagnostic, Location, ModelError, counted, model_text
from spl.dsl.workspace import Workspace

if TYPE_CHECKING:
    from spl.generators.bundle.inputs import BundleMemo
    from spl.generators.bundle.options import BundleOptions
    from spl.generators.bundle.writer import Bundle
    from spl.resolver.resolution.engine import Resolution
    from spl.resolver.resolution.product_line import ProductLine
    from spl.resolver.resolution.product_selection import ProductSelection

# The language module of each model file kind: ``parse_file(path)`` raises ModelError
# with every problem found; ``summary(model)`` is its one-line description.
LANGUAGES = {
    ".tsm": "spl.dsl.tsm.language",
    ".fm": "spl.dsl.fm.language",
    ".rm": "spl.dsl.rm.language",
}


class NothingToCheck(ValueError):
    """A folder given to check holds no model file (a usage error, not a model error)."""


@dataclass(frozen=True)
class ProductWarning:
    """One warning of a derived product, in the one form every reporter gives it
    (docs/ci.md, "A product's warnings"): ``spl resolve`` and ``spl fleet resolve`` print
    it on stderr, ``spl validate`` under the product's line and in its JUnit test case.

    ``text`` is the printed line: ``file:line:col: warning: ... [SPL045]`` for the
    resolver's, ``warning: zenoh/ not written: <reason>`` for an output the bundle goes
    without. ``machine``: it is about this machine, not the product (a picture not
    rendered for want of Graphviz), so it is said but neither counted nor failed by
    ``--strict``: the same product on another machine has no such warning."""

    text: str
    machine: bool = False

    def __str__(self) -> str:
        return self.text


def skip_warning(path: str, reason: str, machine: bool = False) -> ProductWarning:
    """``warning: <path> not written: <reason>``: an output a bundle goes without."""
    diagnostic = Diagnostic(None, f"{path} not written: {reason}", "warning")
    return ProductWarning(str(diagnostic), machine)


@dataclass(frozen=True)
class Derivation:
    """One product derived from a line: the resolution (with its trace and summary), the
    bundle generated from it, not yet written anywhere, and the product's warnings: the
    resolver's in its order, then each skipped output by path. Every reporter reads
    ``warnings``; none puts them together again."""

    resolution: Resolution
    bundle: Bundle
    warnings: tuple[ProductWarning, ...]


def load_line(directory: Path, workspace: Workspace | None = None) -> ProductLine:
    """Parse the line's three models and build its feature formula (ModelError); read as
    the editor's ``workspace`` has them, when given (:mod:`spl.dsl.workspace`)."""
    from spl.resolver.resolution.product_line import load_product_line

    return load_product_line(directory, workspace)


def resolve_product(line: ProductLine, selection: ProductSelection) -> Resolution:
    """Check the selection against the feature model and resolve it (ModelError)."""
    from spl.resolver.resolution.engine import resolve

    return resolve(line, selection)


def derive(
    line: ProductLine,
    selection: ProductSelection,
    options: BundleOptions | None = None,
    memo: BundleMemo | None = None,
) -> Derivation:
    """Resolve the selection and generate its bundle in memory, written as ``options``
    say (default ``spl resolve``'s): every output target or the ones named (``--target``),
    diagrams rendered to SVG unless ``render_diagrams`` is false (their Graphviz source is
    always generated), the Kubernetes objects in the ``--namespace`` chosen, if any.
    ``memo``: the one the caller's bundles share (``spl validate``'s run), else the
    bundle's own."""
    from spl.generators.bundle.writer import build_bundle

    resolution = resolve_product(line, selection)
    bundle = build_bundle(resolution.product, options, memo)
    warnings = (
        *(ProductWarning(str(warning)) for warning in resolution.product.warnings),
        *(
            skip_warning(path, reason, path in bundle.machine_skipped)
            for path, reason in bundle.skipped.items()
        ),
    )
    return Derivation(resolution, bundle, warnings)


def validate(derivation: Derivation) -> list[str]:
    """Every problem of the bundle's files, checked by their consumers' rules (launch
    XSDs, Rapyuta schema and rules, Python compiled, resolved model re-parsed, ...)."""
    from spl.generators.bundle.validation import validate_bundle

    return validate_bundle(derivation.bundle.files, derivation.bundle.memo.clean)


def write(derivation: Derivation, out: Path) -> None:
    """Write the bundle atomically: on any error nothing is left at ``out``."""
    from spl.generators.bundle.writer import write_bundle

    write_bundle(derivation.bundle.files, out)


def read_bundle(bundle: Path) -> tuple[Any, str]:
    """A written bundle's resolved architecture (its ``resolved.tsm``, parsed by spl's
    own .tsm language, so the rehearsal sees what a user could edit and re-read) and its
    product name (from the manifest, else the system's). ModelError when it is none."""
    from spl.dsl.tsm.language import parse_text

    fleet = bundle if (bundle / "fleet.json").is_file() else bundle.parent.parent
    if (fleet / "fleet.json").is_file():  # its robots' cloud nodes run in shared instances
        what = "a fleet bundle" if fleet == bundle else "part of a fleet bundle"
        raise ModelError(
            [
                Diagnostic(
                    None,
                    f"{bundle} is {what} (spl fleet resolve): spl smoke rehearses one "
                    "product's bundle as spl resolve writes it; resolve the robot's product "
                    "with spl resolve to rehearse it",
                )
            ]
        )
    model = bundle / "resolved.tsm"
    if not model.is_file():
        raise ModelError([Diagnostic(None, f"{bundle} is not an spl bundle: no resolved.tsm")])
    system = parse_text(model_text(model), str(model))  # as spl check reads it
    product = system.name
    manifest = bundle / "manifest.json"
    if manifest.is_file():
        with contextlib.suppress(ValueError, AttributeError):  # a damaged one hides nothing
            product = json.loads(manifest.read_text(encoding="utf-8")).get("product", product)
    return system, product


def parse_model(path: Path, workspace: Workspace | None = None) -> tuple[Any, Any]:
    """One model file parsed by the language its suffix names: ``(language, model)``."""
    module_name = LANGUAGES.get(path.suffix)
    if module_name is None:
        known = ", ".join(sorted(LANGUAGES))
        raise ModelError(
            [Diagnostic(Location(str(path), 1, 1), f"unknown model kind (expected {known})")]
        )
    language = importlib.import_module(module_name)
    return language, language.parse_file(path, workspace)


def model_summary(
    path: Path, workspace: Workspace | None = None, analyse: bool = False
) -> tuple[str, list[Diagnostic]]:
    """Parse one model file: its one-line summary and what checking it found beside its
    errors (ModelError with every error). A .tsm is checked without building pyecore
    objects (``tsm.check_file``, what the editor runs too); the problems are the same. A
    UVL or FeatureIDE feature model is read as ``spl analyze`` reads it; with
    ``analyse`` (``spl check FILE``: a feature model checked on its own, not as a
    line's part) any feature model is analysed as ``spl analyze`` analyses it, a void
    model an error, a dead feature a warning (:mod:`spl.resolver.analysis.model_findings`)."""
    if path.suffix == ".tsm":
        from spl.dsl.tsm import language as tsm

        return tsm.summary(tsm.check_file(path, workspace=workspace)), []
    suffix = path.suffix.lower()
    if suffix == ".uvl":  # the plain model spl analyze reads, every level
        from spl.dsl.fm.plain import to_ecore
        from spl.dsl.fm.vocabulary import too_deep
        from spl.dsl.interop.uvl_reader import parse_uvl_plain
        from spl.dsl.interop.uvl_summary import summary
        from spl.dsl.workspace import text_of

        model = parse_uvl_plain(text_of(path, workspace), str(path), path.stem)
        try:  # as every other command builds it: which checks the capability conditions
            to_ecore(model)
        except RecursionError:
            raise ModelError([too_deep(str(path))]) from None
        return summary(model), _feature_model_findings(model) if analyse else []
    if suffix in (".xml", ".fm"):
        from spl.dsl.fm import language as fm
        from spl.dsl.interop.formats import load_feature_model

        model = load_feature_model(path, workspace)
        return fm.summary(model), _feature_model_findings(model) if analyse else []
    language, model = parse_model(path, workspace)
    return language.summary(model), []


def _feature_model_findings(model: Any) -> list[Diagnostic]:
    """A void model's error (raised, as a parse error is), else its dead features."""
    from spl.resolver.analysis.model_findings import feature_model_findings

    found = feature_model_findings(model)
    if any(d.severity == "error" for d in found):
        raise ModelError(found)
    return found


def line_summaries(line: ProductLine) -> dict[Path, str]:
    """The summaries of the files a loaded line parsed, by resolved path."""
    from spl.dsl.fm import language as fm
    from spl.dsl.rm import language as rm
    from spl.dsl.tsm import language as tsm

    base = line.models.path.parent
    return {
        line.models.path.resolve(): rm.summary(line.rm),
        (base / line.rm.tsmPath).resolve(): tsm.summary(line.tsm),
        (base / line.rm.fmPath).resolve(): fm.summary(line.fm),
    }


def check_line(line: ProductLine, workspace: Workspace | None = None) -> list[Diagnostic]:
    """The product-line checks (docs/commands.md, "spl check") of a line whose models load
    (through the editor's ``workspace``, when given)."""
    from spl.resolver.line_checks import check_product_line

    return check_product_line(line, workspace=workspace)


# --- spl check: every model of a file or folder, and the line as a whole ------------

# The product count in the summary line is a courtesy: a bounded, exact count or "unknown".
COUNT_SECONDS = 2.0


def model_files(directory: Path) -> list[Path]:
    return sorted(p for p in directory.iterdir() if p.suffix in LANGUAGES and p.is_file())


def check_models(
    target: Path, count: bool = True, workspace: Workspace | None = None
) -> tuple[dict[str, Any], list[Diagnostic]]:
    """Everything ``spl check`` finds for a file or folder: the ``--json`` object and
    the diagnostics it lists.

    A folder with exactly one .rm is loaded as a product line first, which parses the
    .rm and the .tsm and .fm it names once; their summaries come from that. Files it
    does not cover, and every file when it does not load, are parsed one by one (so a
    problem in a .tsm is reported once, not again through the .rm). A line whose models
    all parse is then checked as a whole; its products are counted (bounded) unless
    ``count`` is false (the language server shows no count). A feature model given on
    its own (a file, not a folder) is also analysed: void is an error, a dead feature a
    warning (:func:`model_summary`); in a folder, the line's checks speak for it.

    The files are read as the editor's ``workspace`` has them, when given; without one,
    the check keeps a workspace of its own, which remembers only the .tsm texts it
    refused: a .tsm the line's loading refused is not built again on its own.
    """
    workspace = workspace if workspace is not None else Workspace()
    files = model_files(target) if target.is_dir() else [target]
    if not files:
        raise NothingToCheck(f"{target} holds no .tsm, .fm or .rm file")
    resolution_models = sum(p.suffix == ".rm" for p in files)
    line = _load_line(target, workspace) if target.is_dir() and resolution_models == 1 else None
    summaries = line_summaries(line) if line is not None else {}
    report: dict[str, Any] = {"target": str(target), "files": [], "diagnostics": []}
    found: list[Diagnostic] = []
    for path in files:
        try:
            summary = summaries.get(path.resolve())
            if summary is None:
                summary, findings = model_summary(path, workspace, not target.is_dir())
                found.extend(findings)
            report["files"].append({"path": str(path), "ok": True, "summary": summary})
        except ModelError as exc:
            report["files"].append({"path": str(path), "ok": False, "summary": None})
            found.extend(exc.diagnostics)
    line_report = None
    if not target.is_dir():
        report["not_a_line"] = None
    elif resolution_models != 1:
        many = resolution_models or "no"
        report["not_a_line"] = f"{many} .rm files; a product line holds one"
        if resolution_models > 1:  # resolve and validate refuse the folder: so does check
            from spl.resolver.resolution.product_line import find_resolution_model

            try:
                find_resolution_model(target)
            except ModelError as exc:
                found.extend(exc.diagnostics)
    elif found:
        report["not_a_line"] = "its models do not parse"
    else:
        report["not_a_line"] = None
        line_report = _check_line(line, count, workspace)
        found.extend(line_report.pop("diagnostics"))
    unique = list(dict.fromkeys(found))
    report["diagnostics"] = [d.as_dict() for d in unique]
    report["line"] = line_report
    for severity in ("error", "warning", "info"):
        report[f"{severity}s"] = sum(d.severity == severity for d in unique)
    report["summary"] = summary_line(report) if target.is_dir() else None
    return report, unique


def _load_line(directory: Path, workspace: Workspace) -> Any:
    """The product line in ``directory``, or None when its models do not load."""
    try:
        return load_line(directory, workspace)
    except ModelError:
        return None  # the files are then parsed one by one to report each problem once


def _check_line(line: Any, count: bool, workspace: Workspace) -> dict[str, Any]:
    diagnostics = check_line(line, workspace)
    products = line.formula.count(COUNT_SECONDS) if count else None
    return {
        "name": line.name,
        "resolution_elements": len(line.rm.elements),
        "products": products.value if products else None,
        "products_note": products.note if products else "not counted",
        "listed_products": len(line.product_files()),
        "diagnostics": diagnostics,
    }


def summary_line(report: dict[str, Any]) -> str:
    """``mapping3d: 9 resolution elements, 12 products, 0 errors, 0 warnings``."""
    line = report["line"]
    counts = f"{counted(report['errors'], 'error')}, {counted(report['warnings'], 'warning')}"
    if report["infos"]:
        counts += f", {counted(report['infos'], 'info')}"
    if line is None:
        return (
            f"{Path(report['target']).resolve().name}: {counts} "
            f"(not checked as a product line: {report['not_a_line']})"
        )
    products = line["products"]
    shown = counted(products, "product") if products is not None else "unknown number of products"
    elements = counted(line["resolution_elements"], "resolution element")
    return f"{line['name']}: {elements}, {shown}, {counts}"
