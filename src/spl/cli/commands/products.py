"""``spl products DIR_OR_FM [--all | --sample t=2 | --random N --seed S] [--json]``.

Lists products of a product line (folder) or of a feature model file (.fm, .uvl,
FeatureIDE .xml). ``--all`` streams every product as the SAT solver finds it (nothing
is materialised, so it starts printing at once even on models with millions of
products); ``--sample t=N`` prints a t-wise covering array; ``--random N`` draws N
distinct products (see :func:`spl.resolver.analysis.sampling.random_products` for the
distribution).

Text output: one product per line, its non-core features comma-separated in model
order (exactly what ``spl resolve --features`` takes; a product of core features only is
named by the root), by their names as the file writes them (one with a blank, comma or
quote in double quotes, as ``spl analyze`` shows it). ``--json``: JSON Lines, one
object per product: ``{"index": i, "selection": [non-core features], "features": [all
selected features]}``. A summary (number of products; for a sample the covered and
invalid combinations and the time) goes to stderr.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import click

FEATURE_MODEL_SUFFIXES = (".fm", ".uvl", ".xml")


def parse_sample(value: str | None) -> int | None:
    """``t=2`` (or ``2``) -> 2; t is 1, 2 or 3."""
    if value is None:
        return None
    match = re.fullmatch(r"(?:t=)?([1-3])", value.strip())
    if not match:
        raise click.BadParameter(f"{value!r}: expected t=1, t=2 or t=3", param_hint="--sample")
    return int(match.group(1))


def load_formula(source: Path):
    """The SAT formula of a product line's feature model or of a feature-model file."""
    from spl.resolver.analysis.formula import FeatureModelFormula

    if source.is_dir():
        from spl.resolver.resolution.product_line import load_product_line

        return load_product_line(source).formula
    if source.suffix.lower() not in FEATURE_MODEL_SUFFIXES:
        raise click.BadParameter(
            f"{source}: expected a product-line folder or a .fm, .uvl or .xml feature model",
            param_hint="DIR_OR_FM",
        )
    from spl.dsl.interop.formats import load_analysable_model

    return FeatureModelFormula(load_analysable_model(source))


@click.command("products")
@click.argument("source", metavar="DIR_OR_FM", type=click.Path(exists=True, path_type=Path))
@click.option(
    "--all",
    "all_products",
    is_flag=True,
    help="every valid product, streamed as found (the default)",
)
@click.option("--sample", metavar="t=N", help="a t-wise covering array (t = 1, 2 or 3)")
@click.option(
    "--random",
    "random_count",
    type=click.IntRange(min=0),
    metavar="N",
    help="N distinct products drawn at random (not uniformly; see docs)",
)
@click.option("--seed", type=int, default=0, show_default=True, help="seed for --random")
@click.option("--json", "as_json", is_flag=True, help="JSON Lines: one object per product")
def command(
    source: Path,
    all_products: bool,
    sample: str | None,
    random_count: int | None,
    seed: int,
    as_json: bool,
) -> None:
    """List the products of a product line or feature model: all of them, a t-wise
    covering sample, or a random selection."""
    from spl.resolver.analysis.sampling import covering_array, product_key, random_products

    t = parse_sample(sample)
    if sum((all_products, t is not None, random_count is not None)) > 1:
        raise click.UsageError("give one of --all, --sample and --random")
    from spl.cli.commands.analyze import shown_name
    from spl.dsl.interop.interchange import written_names

    formula = load_formula(source)
    written = written_names(formula.model)  # names as the file writes them (docs/fm.md)
    root = formula.cnf.names[0]
    note = ""
    if t is not None:
        try:
            found = covering_array(formula, t)
        except ValueError as exc:  # too many combinations for t
            raise click.ClickException(str(exc)) from None
        products = iter(found.products)
        note = (
            f"; they cover all {found.covered} valid {t}-wise combinations "
            f"({found.invalid} invalid ones excluded) in {found.seconds:.2f} s"
        )
    elif random_count is not None:
        products = random_products(formula, random_count, seed)
    else:
        products = formula.products()
    count = 0
    for count, product in enumerate(products, start=1):
        selection = [written.get(n, n) for n in product_key(formula, product) or [root]]
        if as_json:
            features = [written.get(n, n) for n in formula.cnf.names if n in product]
            click.echo(json.dumps({"index": count, "selection": selection, "features": features}))
        else:
            click.echo(",".join(shown_name(name) for name in selection))
    click.echo(f"{count} products{note}", err=True)
