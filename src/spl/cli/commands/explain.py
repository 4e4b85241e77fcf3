"""``spl explain DIR --features ... ELEMENT``: why an element is as it is in a product."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from spl.cli.commands.selection_options import selection_from_options, selection_options

if TYPE_CHECKING:
    from spl.resolver.resolution.engine import Resolution
    from spl.resolver.resolution.product_line import ProductLine


@click.command("explain")
@click.argument("directory", type=click.Path(exists=True, file_okay=False, path_type=Path))
@selection_options
@click.option(
    "--robot",
    metavar="ROBOT_ID",
    help="a private cloud node's instance for this robot alone: why it has one or none",
)
@click.argument("element")
def command(
    directory: Path, features, sharing, settings, capabilities, robot: str | None, element: str
) -> None:
    """Say why ELEMENT is present, absent, migrated or configured as it is in the
    selected product, naming the resolution elements and features responsible with their
    file locations. ELEMENT is a feature, a container, a node, a topic or store (bare,
    or as Container.Topic), a parameter or interface (Node.name), an endpoint
    interface (Container.endpoint.name) or a cloud instance by its tag
    (Container_robotID, Container_group, Container_public), deployed or not."""
    from spl import pipeline
    from spl.resolver.resolution.explanation import qualified_candidates
    from spl.resolver.resolution.instance_explanation import robot_ids

    line = pipeline.load_line(directory)
    selection = selection_from_options(features, sharing, settings, capabilities)
    resolution = pipeline.resolve_product(line, selection)
    known = robot_ids(resolution.product)
    if robot is not None and robot not in known:
        raise click.BadParameter(
            f"no robot {robot!r} in this product (its robots: {', '.join(known) or 'none'})",
            param_hint="--robot",
        )
    lines = explained(line, resolution, element, robot)
    if lines is None:
        candidates = qualified_candidates(line.tsm, resolution.product.system, element)
        hint = f"; did you mean {', '.join(candidates)}?" if candidates else ""
        raise click.BadParameter(f"no element named {element!r} in {directory}{hint}")
    for text in lines:
        click.echo(text)


def explained(
    line: ProductLine, resolution: Resolution, element: str, robot: str | None = None
) -> list[str] | None:
    """Every line ``spl explain`` prints about ``element`` in the resolved product (``spl
    diff`` gives a changed file's reason in these words); None when no model names it."""
    from spl.dsl.fm.language import all_features
    from spl.resolver.resolution.explanation import explanation
    from spl.resolver.resolution.instance_explanation import instance_explanation

    lines: list[str] = []
    if element in {f.name for f in all_features(line.fm)}:
        selected = element in resolution.product.features
        lines.append(f"{element}: {'selected feature' if selected else 'feature not selected'}")
        # the robot's capability that decided it, then the decisions about the feature
        lines += [f"  {c}" for c in resolution.capability_choices if c.feature == element]
        lines += [f"  {e}" for e in resolution.trace.entries if e.subject == element]
    about = explanation(line.tsm, resolution.product, resolution.trace, element, robot)
    instance = instance_explanation(resolution.product, element)
    if about is None and instance is None and not lines:
        return None
    return lines + (about or []) + (instance or [])
