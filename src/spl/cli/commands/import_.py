"""``spl import launch FILE... -o DIR``: a product line from ROS 1 launch files.

The launch files are read by roslaunch's own loader (Debian ``python3-roslaunch``) once
per combination of the ``--arg`` values; what varies between the combinations becomes
features, optional nodes and parameter statements (docs/import.md). Whatever could not
be carried over is listed, located, on stderr and in ``DIR/import-report.txt``. Refused
input (a hostile file, a path outside the package path: exit 1) and a missing ROS (exit
2) write nothing.
"""

from __future__ import annotations

from pathlib import Path

import click

from spl.core.diagnostics import counted


def _line_errors(folder: Path) -> list[str]:
    """The errors ``spl check`` finds in a line written, before it is moved into place."""
    from spl.pipeline import check_models

    return [str(d) for d in check_models(folder, count=False)[1] if d.severity == "error"]


@click.group("import")
def command() -> None:
    """Start a product line from what a team already runs (docs/import.md)."""


@command.command("launch")
@click.argument(
    "files",
    metavar="FILE...",
    nargs=-1,
    required=True,
    type=click.Path(exists=True, dir_okay=False, path_type=Path),
)
@click.option(
    "-o",
    "--out",
    "out",
    required=True,
    type=click.Path(path_type=Path),
    help="The folder of the new product line (new or empty).",
)
@click.option(
    "--arg",
    "arguments",
    multiple=True,
    metavar="NAME=V1,V2,...",
    help="A launch argument and the values products may give it (repeatable).",
)
@click.option(
    "--package-path",
    "package_path",
    multiple=True,
    type=click.Path(exists=True, file_okay=False, path_type=Path),
    help="A folder of ROS packages, for $(find pkg) (repeatable).",
)
@click.option(
    "--robot",
    "robots",
    multiple=True,
    metavar="NODE_PATTERN",
    help="Nodes (ROS name, name or machine; shell pattern) that run on the robot; "
    "the others go to the cloud. Without it, every node is in one cloud container.",
)
@click.option(
    "--graph",
    "graph_master",
    default=None,
    metavar="URI",
    help="Also read the running graph of this ROS master: the nodes it runs get their "
    "topics and services.",
)
def launch(
    graph_master: str | None,
    files: tuple[Path, ...],
    out: Path,
    arguments: tuple[str, ...],
    package_path: tuple[Path, ...],
    robots: tuple[str, ...],
) -> None:
    """Import the ROS 1 launch FILEs into a product line in DIR.

    One product per combination of the --arg values, named by the values joined with
    '_' in the order of the --arg options (products/waffle_pi_hector.yaml).
    """
    from spl.importers.graph.master import GraphUnreadable, read_graph
    from spl.importers.launch import (
        ImportRefused,
        RosMissing,
        import_launch,
        parse_argument,
        refuse_existing,
        write_line,
    )

    try:
        refuse_existing(out)
        parsed = [parse_argument(a) for a in arguments]
        graph = read_graph(graph_master) if graph_master else None
        imported = import_launch(list(files), parsed, list(package_path), robots, graph)
        write_line(imported.files, out, _line_errors)
    except (ImportRefused, GraphUnreadable) as exc:
        click.echo(f"error: {exc}", err=True)
        # a missing program is exit 2, refused input 1 (docs/commands.md)
        raise SystemExit(2 if isinstance(exc, RosMissing) else 1) from None
    for warning in imported.warnings:
        click.echo(str(warning), err=True)
    line = imported.line
    optional = sum(n.optional for n in line.nodes)
    click.echo(
        f"imported {line.name}: {counted(len(line.products), 'product')}, "
        f"{counted(len(line.nodes), 'node')} ({optional} optional), "
        f"{counted(len(imported.warnings), 'thing')} not carried over "
        f"(listed in {out / 'import-report.txt'}); wrote {counted(len(imported.files), 'file')} "
        f"to {out}"
    )


@command.command("graph")
@click.option(
    "-o",
    "--out",
    "out",
    required=True,
    type=click.Path(path_type=Path),
    help="The folder of the new product line (new or empty); its name names the line.",
)
@click.option(
    "--master",
    default=None,
    metavar="URI",
    help="The ROS master to read (default: $ROS_MASTER_URI, else http://localhost:11311/).",
)
@click.option(
    "--package-path",
    "package_path",
    multiple=True,
    type=click.Path(exists=True, file_okay=False, path_type=Path),
    help="A folder of ROS packages, where the nodes' executables are (repeatable).",
)
@click.option(
    "--robot",
    "robots",
    multiple=True,
    metavar="NODE_PATTERN",
    help="Nodes (ROS name or name; shell pattern) that run on the robot.",
)
def graph(
    out: Path, master: str | None, package_path: tuple[Path, ...], robots: tuple[str, ...]
) -> None:
    """Import the ROS 1 graph a running master knows into a product line in DIR.

    Its topics with their types, publishers and subscribers, and its services with their
    types; one product.
    """
    import os
    import re

    from spl.importers.graph import GraphUnreadable, import_graph
    from spl.importers.launch import ImportRefused, refuse_existing, write_line
    from spl.importers.naming import feature_name

    uri = master or os.environ.get("ROS_MASTER_URI") or "http://localhost:11311/"
    stem = re.sub(r"[^A-Za-z0-9_]", "_", out.resolve().name)
    name = feature_name(stem if re.match(r"[A-Za-z]", stem) else f"line_{stem}", set(), "graph")
    try:
        refuse_existing(out)
        imported = import_graph(uri, name, list(package_path), robots)
        write_line(imported.files, out, _line_errors)
    except (ImportRefused, GraphUnreadable) as exc:
        click.echo(f"error: {exc}", err=True)
        raise SystemExit(1) from None
    for warning in imported.warnings:
        click.echo(warning, err=True)
    click.echo(
        f"imported {name}: 1 product, {counted(imported.nodes, 'node')}, "
        f"{counted(len(imported.warnings), 'thing')} not carried over (listed in "
        f"{out / 'import-report.txt'}); wrote {counted(len(imported.files), 'file')} to {out}"
    )
