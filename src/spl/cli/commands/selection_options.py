"""The product-selection options shared by resolve, explain and render."""

from __future__ import annotations

from pathlib import Path
from typing import cast

import click

from spl.resolver.resolution.capabilities import load_capabilities
from spl.resolver.resolution.product_selection import (
    ProductSelection,
    apply_overrides,
    load_selection_file,
    selection_from_list,
)


def selection_options(function):
    function = click.option(
        "--set",
        "settings",
        multiple=True,
        metavar="FEATURE.ATTR=VALUE",
        help="set a feature attribute (overrides the file); VALUE is read by the attribute's "
        "type: a string as typed, an int or double as a decimal number, a bool as true/false",
    )(function)
    function = click.option(
        "--sharing",
        multiple=True,
        metavar="FEATURE=MODE",
        help="sharing mode private|protected|public for a feature (overrides the file)",
    )(function)
    function = click.option(
        "--capabilities",
        type=click.Path(exists=True, dir_okay=False, path_type=Path),
        metavar="ROBOT.yaml",
        help="a robot capability file: the capabilities choose features (with --features or alone)",
    )(function)
    return click.option(
        "--features",
        metavar="LIST|FILE.yaml",
        help="selected features, comma-separated, or a product selection YAML file",
    )(function)


def selection_from_options(
    features: str | None, sharing, settings, capabilities: Path | None = None
) -> ProductSelection:
    """The selection of ``--features`` (a list or a file) and ``--capabilities``, with the
    ``--sharing`` and ``--set`` overrides; at least one of the two must be given."""
    if features is None and capabilities is None:
        raise click.UsageError("give --features LIST|FILE.yaml, --capabilities ROBOT.yaml or both")
    if features is None:
        selection = ProductSelection(name=cast(Path, capabilities).stem, features=[])
    elif features.endswith((".yaml", ".yml")):
        if not Path(features).is_file():
            raise click.BadParameter(f"{features}: no such file", param_hint="--features")
        selection = load_selection_file(features)
    else:
        selection = selection_from_list(features)
        if capabilities is not None:  # the robot names the product; the list completes it
            selection.name = capabilities.stem
    if capabilities is not None:
        selection.capabilities = load_capabilities(capabilities)
    return apply_overrides(selection, list(sharing), list(settings))
