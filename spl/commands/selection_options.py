"""The product-selection options shared by resolve, explain and render."""

from __future__ import annotations

from pathlib import Path

import click

from spl.resolver.product_selection import (
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
        help="set a feature attribute (overrides the file)",
    )(function)
    function = click.option(
        "--sharing",
        multiple=True,
        metavar="FEATURE=MODE",
        help="sharing mode private|protected|public for a feature (overrides the file)",
    )(function)
    return click.option(
        "--features",
        required=True,
        metavar="LIST|FILE.yaml",
        help="selected features, comma-separated, or a product selection YAML file",
    )(function)


def selection_from_options(features: str, sharing, settings) -> ProductSelection:
    if features.endswith((".yaml", ".yml")):
        if not Path(features).is_file():
            raise click.BadParameter(f"{features}: no such file", param_hint="--features")
        selection = load_selection_file(features)
    else:
        selection = selection_from_list(features)
    return apply_overrides(selection, list(sharing), list(settings))
