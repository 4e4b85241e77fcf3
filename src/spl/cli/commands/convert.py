"""``spl convert IN OUT``: a feature model between .fm, UVL and FeatureIDE XML.

The formats come from the suffixes, so community models (UVL, FeatureIDE) can be
turned into .fm files and ours opened in FeatureIDE or flamapy. Every output is
rendered before any is written, each atomically: a model that cannot be expressed in
the target format leaves no file (docs/fm.md, "Conversion").
"""

from __future__ import annotations

from pathlib import Path

import click


@click.command("convert")
@click.argument("source", metavar="IN", type=click.Path(dir_okay=False, path_type=Path))
@click.argument("target", metavar="OUT", type=click.Path(dir_okay=False, path_type=Path))
def command(source: Path, target: Path) -> None:
    """Convert the feature model IN to OUT (.fm, .uvl or FeatureIDE .xml, by suffix).

    \b
    What each target keeps:
      UVL    every language level: the tree, constraints, typed features, feature
             cardinalities, arithmetic, attribute and string constraints, aggregates,
             attributes (nested and vector values as written), with an include
             section naming the levels used; a composed UVL model keeps its
             submodels, each written at its import path beside OUT.
      .fm, FeatureIDE XML
             the Boolean level: the tree, Boolean constraints, attributes with fixed
             values. A UVL model with typed features, feature cardinalities or
             equations is refused at its first such part, located; nothing is written.

    Feature names UVL or FeatureIDE allow but .fm does not (spaces, dots, keywords)
    are renamed to identifiers; the original name is kept in an attribute
    original_name and written back when exporting.
    """
    from spl.core.atomic_write import write_atomically
    from spl.dsl.interop.formats import FORMATS, converted_files, unsupported_format_message

    for path, role in ((source, "IN"), (target, "OUT")):
        if path.suffix.lower() not in FORMATS:
            raise click.UsageError(f"{role}: {unsupported_format_message(path)}")
    if not source.is_file():
        raise click.UsageError(f"IN: {source} does not exist")
    if not target.parent.is_dir():
        raise click.UsageError(f"OUT: directory {target.parent} does not exist")
    if target.exists() and target.samefile(source):  # the rename would replace the input
        raise click.UsageError(f"OUT: {target} is IN itself; give another file")
    summary, files = converted_files(source, target)
    read = {path.resolve() for path, _ in files.values()}
    written = []
    for path, (converted, data) in files.items():
        if path != target and path.resolve() == converted.resolve():
            continue  # a submodel converted onto itself: its file is already what it reads
        if path.resolve() in read:
            raise click.UsageError(
                f"OUT: writing {path} would replace an input; give another folder"
            )
        written.append((path, data))
    for path, data in written:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_atomically(path, data)
    click.echo(f"{source} -> {target}: {summary}")
    for path, _ in written[1:]:
        click.echo(f"  and its submodel {path}")
