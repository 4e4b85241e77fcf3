"""``spl merge-junit SHARD.xml... -o FILE``: the JUnit report of a sharded run.

Each CI job of a matrix runs ``spl validate ... --shard K/N --junit shard-K.xml``; the
merge puts the N reports back into the one the unsharded run writes, byte for byte, and
refuses a missing, repeated or foreign shard, so a matrix never reports a partial run as
whole. Exit 1 when a product failed, as ``spl validate`` does.
"""

from __future__ import annotations

import sys
from pathlib import Path

import click


@click.command("merge-junit")
@click.argument(
    "reports",
    metavar="SHARD.xml...",
    nargs=-1,
    required=True,
    type=click.Path(exists=True, dir_okay=False, path_type=Path),
)
@click.option(
    "--output",
    "-o",
    required=True,
    type=click.Path(dir_okay=False, path_type=Path),
    help="the merged report",
)
def command(reports: tuple[Path, ...], output: Path) -> None:
    """Merge the JUnit reports of the shards of one `spl validate --shard K/N` run."""
    from spl.core.atomic_write import write_atomically
    from spl.validation.junit import ReportProblem, merge_junit, summary_of

    try:
        data = merge_junit([(str(path), path.read_bytes()) for path in reports])
    except ReportProblem as exc:
        click.echo(f"error: {exc}", err=True)
        sys.exit(1)
    output.parent.mkdir(parents=True, exist_ok=True)
    write_atomically(output, data)
    passed, failed = summary_of(data)
    click.echo(f"{output}: {len(reports)} shards, {passed} passed, {failed} failed")
    if failed:
        sys.exit(1)
