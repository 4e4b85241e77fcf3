"""``spl check FILE_OR_DIR``: parse and check models, print a one-line summary each.

For a product-line folder (one .rm naming its .tsm and .fm) the line is then checked
as a whole (SPEC section 8, :mod:`spl.resolver.line_checks`): elements that can never
be active, optional nodes no product contains, conflicts some product would hit,
features with no effect, listed products that do not resolve. Only errors fail the
check; warnings and infos are printed and exit 0, so CI can adopt the check early.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click

from spl import pipeline
from spl.diagnostics import Diagnostic, ModelError, counted

# The product count in the summary line is a courtesy: a bounded, exact count or "unknown".
COUNT_SECONDS = 2.0


def check_file(path: Path) -> str:
    return f"{path}: ok: {pipeline.model_summary(path)}"


def model_files(directory: Path) -> list[Path]:
    return sorted(p for p in directory.iterdir() if p.suffix in pipeline.LANGUAGES and p.is_file())


def check_target(target: Path) -> tuple[dict[str, Any], list[Diagnostic]]:
    """Everything ``spl check`` finds for a file or folder: the ``--json`` object and
    the diagnostics it lists.

    A folder with exactly one .rm is loaded as a product line first, which parses the
    .rm and the .tsm and .fm it names once; their summaries come from that. Files it
    does not cover, and every file when it does not load, are parsed one by one (so a
    problem in a .tsm is reported once, not again through the .rm). A line whose models
    all parse is then checked as a whole.
    """
    files = model_files(target) if target.is_dir() else [target]
    if not files:
        raise click.UsageError(f"{target} holds no .tsm, .fm or .rm file")
    resolution_models = sum(p.suffix == ".rm" for p in files)
    line = _load_line(target) if target.is_dir() and resolution_models == 1 else None
    summaries = pipeline.line_summaries(line) if line is not None else {}
    report: dict[str, Any] = {"target": str(target), "files": [], "diagnostics": []}
    found: list[Diagnostic] = []
    for path in files:
        try:
            summary = summaries.get(path.resolve()) or pipeline.model_summary(path)
            report["files"].append({"path": str(path), "ok": True, "summary": summary})
        except ModelError as exc:
            report["files"].append({"path": str(path), "ok": False, "summary": None})
            found.extend(exc.diagnostics)
    line_report = None
    if not target.is_dir():
        report["not_a_line"] = None
    elif resolution_models != 1:
        count = resolution_models or "no"
        report["not_a_line"] = f"{count} .rm files; a product line holds one"
    elif found:
        report["not_a_line"] = "its models do not parse"
    else:
        report["not_a_line"] = None
        line_report = _check_line(line)
        found.extend(line_report.pop("diagnostics"))
    unique = list(dict.fromkeys(found))
    report["diagnostics"] = [d.as_dict() for d in unique]
    report["line"] = line_report
    for severity in ("error", "warning", "info"):
        report[f"{severity}s"] = sum(d.severity == severity for d in unique)
    report["summary"] = summary_line(report) if target.is_dir() else None
    return report, unique


def _load_line(directory: Path) -> Any:
    """The product line in ``directory``, or None when its models do not load."""
    try:
        return pipeline.load_line(directory)
    except ModelError:
        return None  # the files are then parsed one by one to report each problem once


def _check_line(line: Any) -> dict[str, Any]:
    diagnostics = pipeline.check_line(line)
    count = line.formula.count(COUNT_SECONDS)
    return {
        "name": line.name,
        "resolution_elements": len(line.rm.elements),
        "products": count.value,
        "products_note": count.note,
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


@click.command("check")
@click.argument("target", type=click.Path(exists=True, path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object instead of text.")
def command(target: Path, as_json: bool) -> None:
    """Parse and check a model file (.tsm, .fm, .rm) or a product-line folder.

    Every problem is printed as FILE:LINE:COL: SEVERITY: MESSAGE [CODE]; the exit
    status is 1 when any error was found (warnings and infos exit 0).
    """
    report, found = check_target(target)
    if as_json:
        click.echo(json.dumps(report, indent=2, sort_keys=True))
        if report["errors"]:
            raise click.exceptions.Exit(1)
        return
    for entry in report["files"]:
        if entry["ok"]:
            click.echo(f"{entry['path']}: ok: {entry['summary']}")
    if not target.is_dir():  # one file: its summary or its errors, as always
        if found:
            raise ModelError(found)
        return
    for diagnostic in found:
        click.echo(str(diagnostic), err=True)
    click.echo(report["summary"])
    if report["errors"]:
        raise click.exceptions.Exit(1)
