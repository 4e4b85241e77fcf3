"""``spl convert IN OUT``: a feature model between .fm, UVL and FeatureIDE XML.

The formats come from the suffixes, so community models (UVL, FeatureIDE) can be
turned into .fm files and ours opened in FeatureIDE or flamapy. The output is written
atomically: a model that cannot be expressed in the target format leaves no file.
"""

from __future__ import annotations

from pathlib import Path

import click


@click.command("convert")
@click.argument("source", metavar="IN", type=click.Path(dir_okay=False, path_type=Path))
@click.argument("target", metavar="OUT", type=click.Path(dir_okay=False, path_type=Path))
def command(source: Path, target: Path) -> None:
    """Convert the feature model IN to OUT (.fm, .uvl or FeatureIDE .xml, by suffix).

    Feature names UVL or FeatureIDE allow but .fm does not (spaces, dots, keywords)
    are renamed to identifiers; the original name is kept in an attribute
    original_name and written back when exporting. A UVL model of the Arithmetic or
    Type level (typed features, feature cardinalities, equations) is refused, located:
    the three formats' writers carry the Boolean level.
    """
    from spl.dsl.fm.language import summary
    from spl.dsl.interop.formats import (
        FORMATS,
        load_feature_model,
        save_feature_model,
        unsupported_format_message,
    )

    for path, role in ((source, "IN"), (target, "OUT")):
        if path.suffix.lower() not in FORMATS:
            raise click.UsageError(f"{role}: {unsupported_format_message(path)}")
    if not source.is_file():
        raise click.UsageError(f"IN: {source} does not exist")
    if not target.parent.is_dir():
        raise click.UsageError(f"OUT: directory {target.parent} does not exist")
    if target.exists() and target.samefile(source):  # the rename would replace the input
        raise click.UsageError(f"OUT: {target} is IN itself; give another file")
    model = load_feature_model(
        source, carried_by=f"spl convert to {FORMATS[target.suffix.lower()]}"
    )
    save_feature_model(model, target)
    click.echo(f"{source} -> {target}: {summary(model)}")
