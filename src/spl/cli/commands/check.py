"""``spl check FILE_OR_DIR``: parse and check models, print a one-line summary each.

For a product-line folder (one .rm naming its .tsm and .fm) the line is then checked
as a whole (docs/commands.md, "spl check"; :mod:`spl.resolver.line_checks`): elements that can never
be active, optional nodes no product contains, conflicts some product would hit,
features with no effect, listed products that do not resolve. Only errors fail the
check; warnings and infos are printed and exit 0, so CI can adopt the check early.
"""

from __future__ import annotations

import json
from pathlib import Path

import click

from spl import pipeline
from spl.core.diagnostics import ModelError


@click.command("check")
@click.argument("target", type=click.Path(exists=True, path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object instead of text.")
def command(target: Path, as_json: bool) -> None:
    """Parse and check a model file (.tsm, .fm, .rm; a .uvl or FeatureIDE .xml feature
    model) or a product-line folder.

    Every problem is printed as FILE:LINE:COL: SEVERITY: MESSAGE [CODE]; the exit
    status is 1 when any error was found (warnings and infos exit 0).
    """
    try:
        report, found = pipeline.check_models(target)
    except pipeline.NothingToCheck as exc:
        raise click.UsageError(str(exc)) from None
    if as_json:
        click.echo(json.dumps(report, indent=2, sort_keys=True))
        if report["errors"]:
            raise click.exceptions.Exit(1)
        return
    for entry in report["files"]:
        if entry["ok"]:
            click.echo(f"{entry['path']}: ok: {entry['summary']}")
    if not target.is_dir():  # one file: its summary or its errors, as always
        if report["errors"]:
            raise ModelError(found)
        for diagnostic in found:  # a parsed model's warnings (a dead feature): exit 0
            click.echo(str(diagnostic), err=True)
        return
    for diagnostic in found:
        click.echo(str(diagnostic), err=True)
    click.echo(report["summary"])
    if report["errors"]:
        raise click.exceptions.Exit(1)
