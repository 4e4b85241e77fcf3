"""``spl analyze FM [--json]``: feature-model analysis of a ``.fm``, ``.uvl`` or ``.xml``.

One incremental SAT solver answers every question (satisfiable, core, dead,
false-optional); the product count is exact or, past its bound, ``null`` with a note —
a number printed here is never an estimate.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import click

from spl.diagnostics import counted


def analysis_report(model: Any, count_seconds: float) -> dict[str, Any]:
    """The analysis as the JSON object ``spl analyze --json`` prints."""
    from spl.resolver.analysis import FeatureModelFormula

    start = time.perf_counter()
    with FeatureModelFormula(model) as formula:
        satisfiable = formula.satisfiable()
        core = formula.core_features()
        dead = formula.dead_features()
        false_optional = formula.false_optional_features()
        count = formula.count(count_seconds)
        features = formula.cnf.num_features
    return {
        "name": model.name,
        "features": features,
        "constraints": len(model.constraints),
        "satisfiable": satisfiable,
        "products": count.value,
        "products_note": count.note,
        "core": core,
        "dead": dead,
        "false_optional": false_optional,
        "seconds": round(time.perf_counter() - start, 3),
    }


def _names(names: list[str]) -> str:
    return ", ".join(names) if names else "-"


def text_report(path: Path, report: dict[str, Any]) -> list[str]:
    products = report["products"]
    shown = str(products) if products is not None else f"unknown ({report['products_note']})"
    return [
        f"{report['name']} ({path}): {counted(report['features'], 'feature')}, "
        f"{counted(report['constraints'], 'constraint')}",
        f"  satisfiable:    {'yes' if report['satisfiable'] else 'no (void feature model)'}",
        f"  products:       {shown}",
        f"  core ({len(report['core'])}): {_names(report['core'])}",
        f"  dead ({len(report['dead'])}): {_names(report['dead'])}",
        f"  false-optional ({len(report['false_optional'])}): {_names(report['false_optional'])}",
        f"  analysed in {report['seconds']:.3f} s",
    ]


@click.command("analyze")
@click.argument("model_file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="print one JSON object")
@click.option(
    "--count-seconds",
    type=click.FloatRange(min=0.0),
    default=10.0,
    show_default=True,
    help="time bound for the exact product count (past it: null and a note)",
)
def command(model_file: Path, as_json: bool, count_seconds: float) -> None:
    """Analyse a feature model (.fm, .uvl, FeatureIDE .xml): satisfiable, number of
    products, core, dead and false-optional features."""
    from spl.dsl.fm_formats import load_feature_model

    model = load_feature_model(model_file)
    report = analysis_report(model, count_seconds)
    if as_json:
        click.echo(json.dumps(report, sort_keys=True))
    else:
        for line in text_report(model_file, report):
            click.echo(line)
