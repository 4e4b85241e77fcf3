"""``spl explain DIR --features ... ELEMENT``: why an element is as it is in a product."""

from __future__ import annotations

from pathlib import Path

import click

from spl.commands.selection_options import selection_from_options, selection_options


@click.command("explain")
@click.argument("directory", type=click.Path(exists=True, file_okay=False, path_type=Path))
@selection_options
@click.argument("element")
def command(directory: Path, features, sharing, settings, capabilities, element: str) -> None:
    """Say why ELEMENT (a node, topic, interface, container or feature) is present,
    absent, migrated or configured as it is in the selected product, naming the
    resolution elements and features responsible with their file locations."""
    from spl import pipeline
    from spl.dsl.fm import all_features

    line = pipeline.load_line(directory)
    selection = selection_from_options(features, sharing, settings, capabilities)
    resolution = pipeline.resolve_product(line, selection)
    system = resolution.product.system
    placed = {n.name: c.name for c in system.containers for n in c.nodes}
    features = {f.name for f in all_features(line.fm)}
    chosen = [c for c in resolution.capability_choices if c.feature == element]
    if element in placed:
        click.echo(f"{element}: present in container {placed[element]}")
    elif element in resolution.product.features:
        click.echo(f"{element}: selected feature")
    elif element in features:  # the selection, its completion or a capability left it out
        click.echo(f"{element}: feature not selected")
    for choice in chosen:  # the robot's capability that decided it
        click.echo(f"  {choice}")
    entries = resolution.trace.about(element)
    if not entries and not chosen and element not in placed:
        if element not in _template_names(line.tsm) | features:
            raise click.BadParameter(f"no element named {element!r} in {directory}")
        click.echo(f"{element}: nothing in this product decided about it")
        return
    for entry in entries:
        click.echo(f"  {entry}")


def _template_names(system) -> set[str]:
    names = {c.name for c in system.containers}
    for container in system.containers:
        names |= {n.name for n in container.nodes} | {t.name for t in container.topics}
        names |= {s.name for s in container.stores}
    return names
