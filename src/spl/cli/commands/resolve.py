"""``spl resolve DIR --features LIST|FILE.yaml [-o OUT]``: derive one product, write its bundle."""

from __future__ import annotations

from pathlib import Path

import click

from spl.cli.commands.selection_options import selection_from_options, selection_options


def _targets(context: click.Context, parameter: click.Parameter, value: str | None):
    from spl.generators.bundle.writer import choose_targets

    try:
        return choose_targets(value)
    except ValueError as error:
        raise click.BadParameter(str(error)) from None


def namespace_option(command):
    """``--namespace NAME``: the Kubernetes namespace of the manifests (a DNS-1123
    label, checked before anything is resolved)."""

    def check(context: click.Context, parameter: click.Parameter, value: str | None):
        from spl.generators.workloads.security import checked_namespace

        try:
            return None if value is None else checked_namespace(value)
        except ValueError as error:
            raise click.BadParameter(str(error)) from None

    return click.option(
        "--namespace",
        metavar="NAME",
        callback=check,
        help="Kubernetes namespace of kubernetes/ and deploy/kubernetes/ "
        "(default: the product's or fleet's name as a DNS-1123 label)",
    )(command)


@click.command("resolve")
@click.argument("directory", type=click.Path(exists=True, file_okay=False, path_type=Path))
@selection_options
@click.option(
    "-o", "--out", type=click.Path(path_type=Path), help="bundle folder (default: build/PRODUCT)"
)
@click.option(
    "--target",
    "targets",
    metavar="LIST",
    callback=_targets,
    help="outputs to write, comma-separated: ros1, ros2, rapyuta, diagrams, services, "
    "kubernetes, zenoh (default: all)",
)
@namespace_option
def command(
    directory: Path,
    features: str | None,
    sharing,
    settings,
    capabilities,
    out: Path | None,
    targets: tuple[str, ...],
    namespace: str | None,
) -> None:
    """Derive the product selected by --features (a list or a YAML file) and/or chosen by
    a robot's --capabilities, and write its deployment bundle. The bundle is written
    atomically: on any error nothing is left. An output the product or this machine
    cannot have (zenoh/ Zenoh cannot carry, architecture.svg without Graphviz) is left out
    with a one-line warning on stderr; the rest of the bundle is written, exit 0."""
    from spl import pipeline
    from spl.generators.bundle.options import BundleOptions
    from spl.resolver.resolution.engine import summary_lines

    options = BundleOptions(targets=targets, namespace=namespace)
    line = pipeline.load_line(directory)
    selection = selection_from_options(features, sharing, settings, capabilities)
    derivation = pipeline.derive(line, selection, options)
    resolution = derivation.resolution
    out = out or Path("build") / resolution.product.name
    pipeline.write(derivation, out)
    for line_text in summary_lines(resolution):
        click.echo(line_text)
    for warning in derivation.warnings:  # the resolver's, then each output left out
        click.echo(str(warning), err=True)
    click.echo(f"  wrote {len(derivation.bundle.files)} files to {out}")
