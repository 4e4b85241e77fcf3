"""``spl render DIR [--features ...] [--what fm|tsm|product] -o FILE.svg``: diagrams.

Three views of one product line: its feature model (with a selection highlighted when
``--features`` is given), its template architecture (the TSM as written), or the
resolved architecture of one product. The output format follows the file suffix:
``.svg`` and ``.png`` need Graphviz's ``dot`` program, ``.dot`` is the Graphviz source
and needs nothing (render it later with ``dot -Tsvg``). Without ``dot`` an SVG or PNG
is refused with one line and exit status 2, as for any program a command needs.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, cast

import click

from spl.cli.commands.selection_options import selection_from_options

if TYPE_CHECKING:
    from spl.resolver.resolution.engine import Resolution

VIEWS = ("fm", "tsm", "product")


@click.command("render")
@click.argument("directory", type=click.Path(exists=True, file_okay=False, path_type=Path))
@click.option(
    "--features",
    default=None,
    metavar="LIST|FILE.yaml",
    help="selected features (needed for --what product; highlights them with --what fm)",
)
@click.option(
    "--sharing",
    multiple=True,
    metavar="FEATURE=MODE",
    help="sharing mode private|protected|public for a feature (overrides the file)",
)
@click.option(
    "--set",
    "settings",
    multiple=True,
    metavar="FEATURE.ATTR=VALUE",
    help="set a feature attribute (overrides the file)",
)
@click.option(
    "--what",
    type=click.Choice(VIEWS),
    default=None,
    help="diagram to draw (default: product with --features, else tsm)",
)
@click.option(
    "-o",
    "--out",
    required=True,
    type=click.Path(dir_okay=False, path_type=Path),
    help="output file, .svg or .png (needs Graphviz), or .dot (the Graphviz source)",
)
def command(
    directory: Path,
    features: str | None,
    sharing: tuple[str, ...],
    settings: tuple[str, ...],
    what: str | None,
    out: Path,
) -> None:
    """Draw the feature model, the template architecture or a resolved product of the
    product line in DIRECTORY, in the notation of the mapping paper's Fig. 4 and Fig. 5
    (docs/index.md names the paper)."""
    if out.suffix.lower() not in (".svg", ".png", ".dot"):
        raise click.BadParameter(f"{out}: the file must end in .svg, .png or .dot", param_hint="-o")
    what = what or ("product" if features else "tsm")
    if what == "product" and not features:
        raise click.UsageError("--what product needs --features")

    import graphviz

    from spl import pipeline
    from spl.dsl.fm.printer import format_formula
    from spl.generators.diagrams import (
        architecture as diagrams,
        feature_model as feature_model_diagram,
        graphviz_output,
    )

    line = pipeline.load_line(directory)
    resolution = None
    if features:
        selection = selection_from_options(features, sharing, settings)
        resolution = pipeline.resolve_product(line, selection)
    if what == "fm":
        selected = set(resolution.product.features) if resolution else None
        graph = feature_model_diagram.feature_model_graph(
            line.fm, selected, formula_text=format_formula
        )
    elif what == "tsm":
        graph = diagrams.architecture_graph(line.tsm)
    else:
        product = cast("Resolution", resolution).product  # (a product needs --features)
        graph = diagrams.architecture_graph(product.system, product)
    try:
        graphviz_output.render(graph, out)
    except graphviz.ExecutableNotFound:
        click.echo(
            f"error: {out.name} not written: {graphviz_output.DOT_MISSING} "
            f"(or write the source with -o {out.with_suffix('.dot').name})",
            err=True,
        )
        sys.exit(2)
    click.echo(f"wrote {out}")
