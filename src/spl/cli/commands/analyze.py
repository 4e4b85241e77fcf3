"""``spl analyze FM [--json] [--count | --count-seconds S]``: feature-model analysis of a
``.fm``, ``.uvl`` or ``.xml``.

One incremental SAT solver answers every question (satisfiable, core, dead,
false-optional), an SMT solver (z3) for a UVL model of the Arithmetic or Type level
(typed features, feature cardinalities, equations: docs/analysis.md); the product
count is exact or, past its bound, ``null`` with a note — a number printed here is
never an estimate. A UVL file is analysed from plain objects
(no pyecore model is built), so the command costs little more than reading the text.
"""

from __future__ import annotations

import json
import re
import time
from pathlib import Path
from typing import Any

import click

from spl.core.diagnostics import counted

# Without --count or --count-seconds the count may take as long as reading and analysing
# the model took, and at least this long: it never makes the command much slower than
# the analysis the user asked for.
DEFAULT_COUNT_SECONDS = 1.0
# Names printed bare in the text report; any other is quoted (docs/analysis.md).
_UNQUOTED = re.compile(r'[^\s,"]+')


def analysis_report(
    model: Any, count_seconds: float | None, default_count_since: float | None = None
) -> dict[str, Any]:
    """The analysis as the JSON object ``spl analyze --json`` prints.

    ``count_seconds`` bounds the exact count (None: no time bound). With
    ``default_count_since`` (a ``time.perf_counter()`` taken before the model was read)
    the bound is instead the time spent since then, at least
    :data:`DEFAULT_COUNT_SECONDS`.
    """
    from spl.dsl.interop.interchange import written_names
    from spl.dsl.interop.uvl_typed import is_typed
    from spl.resolver.analysis.formula import FeatureModelFormula

    start = time.perf_counter()
    typed = is_typed(model)
    if typed:  # the Arithmetic and Type levels: on z3 (docs/analysis.md)
        from spl.resolver.analysis.smt import SmtFormula

        solver: Any = SmtFormula(model)
    else:
        solver = FeatureModelFormula(model)
    with solver as formula:
        satisfiable = formula.satisfiable()
        core = formula.core_features()
        dead = formula.dead_features()
        false_optional = formula.false_optional_features()
        if default_count_since is not None:
            spent = time.perf_counter() - default_count_since
            count_seconds = round(max(DEFAULT_COUNT_SECONDS, spent), 1)
        count = formula.count(count_seconds)
        features = formula.cnf.num_features
    written = written_names(model)

    def as_written(names: list[str]) -> list[str]:
        return sorted(written.get(name, name) for name in names)

    return {
        "name": getattr(model, "written_name", model.name),  # a UVL file's, as written
        "features": features,
        "constraints": len(model.constraints) + len(getattr(model, "equations", ())),
        "satisfiable": satisfiable,
        "products": count.value,
        "products_note": count.note,
        "core": as_written(core),
        "dead": as_written(dead),
        "false_optional": as_written(false_optional),
        "seconds": round(time.perf_counter() - start, 3),
    }


def _names(names: list[str]) -> str:
    """Names as written, comma-separated (:func:`shown_name`)."""
    return ", ".join(shown_name(name) for name in names) if names else "-"


def shown_name(name: str) -> str:
    """A feature name as written; one a comma list would make ambiguous (a blank, a
    comma, a quote in it) quoted as UVL quotes it."""
    return name if _UNQUOTED.fullmatch(name) else json.dumps(name, ensure_ascii=False)


def text_report(path: Path, report: dict[str, Any]) -> list[str]:
    products = report["products"]
    if products is not None:
        shown = str(products)
    else:
        shown = f"unknown ({report['products_note']}; --count counts without a time bound)"
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
    "--count",
    "count_unbounded",
    is_flag=True,
    help="count the products exactly, however long it takes",
)
@click.option(
    "--count-seconds",
    type=click.FloatRange(min=0.0),
    default=None,
    help="time bound for the exact product count (past it: null and a note); default: "
    f"as long as the analysis took, at least {DEFAULT_COUNT_SECONDS:g} s",
)
def command(
    model_file: Path, as_json: bool, count_unbounded: bool, count_seconds: float | None
) -> None:
    """Analyse a feature model (.fm, .uvl, FeatureIDE .xml): satisfiable, number of
    products, core, dead and false-optional features."""
    from spl.dsl.interop.formats import FORMATS, load_analysable_model

    if count_unbounded and count_seconds is not None:
        raise click.UsageError("give either --count or --count-seconds")
    if count_seconds is not None and count_seconds != count_seconds:  # NaN passes FloatRange
        raise click.BadParameter("nan is not a number of seconds", param_hint="--count-seconds")
    if model_file.suffix.lower() not in FORMATS:  # a usage error, as spl products says
        raise click.BadParameter(
            f"{model_file}: expected a .fm, .uvl or .xml feature model", param_hint="MODEL_FILE"
        )
    started = time.perf_counter()
    model = load_analysable_model(model_file, typed=True)
    default = count_seconds is None and not count_unbounded
    report = analysis_report(model, count_seconds, started if default else None)
    if model_file.suffix.lower() == ".xml":  # FeatureIDE names a model by its file
        report["name"] = model_file.stem
    if as_json:
        click.echo(json.dumps(report, sort_keys=True))
    else:
        for line in text_report(model_file, report):
            click.echo(line)
