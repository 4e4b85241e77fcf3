"""``spl diff OLD NEW [--json] [--count | --count-seconds S]``: what an edit did to a
feature model (.fm, .uvl or FeatureIDE .xml, the two in any formats).

The answer is a report, not a verdict: the exit status is 0 whatever the edit is, 1
only for a model that cannot be read. What it means is docs/evolution.md; the work is
:mod:`spl.resolver.analysis.operations.edit_classification`. As with ``spl analyze``,
the counts never make the command slow by default: they may take as long as reading
and comparing took, at least 1 s, and a count not finished by then is ``null``.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import click

from spl.cli.commands.analyze import DEFAULT_COUNT_SECONDS

SHOWN = 10  # list items a text report shows before "... and N more"
MEANINGS = {
    "refactoring": "the same products",
    "generalization": "products added, none removed",
    "specialization": "products removed, none added",
    "arbitrary": "products added and removed",
}


def diff_report(old: Any, new: Any, count_seconds: float | None, since: float | None) -> dict:
    """The comparison as the JSON object ``spl diff --json`` prints. ``count_seconds``
    bounds the counts (None: no bound); with ``since`` (a ``time.perf_counter()`` taken
    before the models were read) the bound is instead the time spent since then, at
    least :data:`~spl.cli.commands.analyze.DEFAULT_COUNT_SECONDS`."""
    from spl.resolver.analysis.operations.edit_classification import ModelEdit

    with ModelEdit(old, new) as edit:
        old_not_new, new_not_old = edit.witnesses()
        if since is not None:
            count_seconds = round(max(DEFAULT_COUNT_SECONDS, time.perf_counter() - since), 1)
        removed_count, added_count = edit.counts(count_seconds)
        return {
            "classification": edit.classification,
            "added": edit.added,
            "removed": edit.removed,
            "moved": [
                {"feature": m.feature, "old_parent": m.old_parent, "new_parent": m.new_parent}
                for m in edit.moved
            ],
            "constraints": {
                "added": edit.constraints_added,
                "removed": edit.constraints_removed,
            },
            "witnesses": {"old_not_new": old_not_new, "new_not_old": new_not_old},
            "counts": {"old_not_new": removed_count.value, "new_not_old": added_count.value},
            "counts_note": removed_count.note or added_count.note,
        }


def _listed(items: list[str], separator: str = ", ") -> str:
    if not items:
        return "-"
    shown = separator.join(items[:SHOWN])
    return shown + (f" ... and {len(items) - SHOWN} more" if len(items) > SHOWN else "")


def _count(value: int | None, note: str, unbounded: str) -> str:
    return str(value) if value is not None else f"unknown ({note}{unbounded})"


def text_report(old: Path, new: Path, report: dict, bounded: bool = True) -> list[str]:
    """The report for people; ``bounded``: the counts had a time bound."""
    kind = report["classification"]
    counts, witnesses = report["counts"], report["witnesses"]
    note = report["counts_note"]
    hint = "; --count counts without a time bound" if bounded else ""
    moves = [
        f"{m['feature']} ({m['old_parent'] or '(root)'} -> {m['new_parent'] or '(root)'})"
        for m in report["moved"]
    ]
    added, removed = report["constraints"]["added"], report["constraints"]["removed"]
    lines = [
        f"{old} -> {new}: {kind} ({MEANINGS[kind]})",
        f"  products removed: {_count(counts['old_not_new'], note, hint)}",
        f"  products added:   {_count(counts['new_not_old'], note, hint)}",
    ]
    for label, witness in (
        ("a removed product", witnesses["old_not_new"]),
        ("an added product", witnesses["new_not_old"]),
    ):
        if witness is not None:
            lines.append(f"  {label} ({len(witness)} features): {_listed(witness)}")
    return [
        *lines,
        f"  features added ({len(report['added'])}): {_listed(report['added'])}",
        f"  features removed ({len(report['removed'])}): {_listed(report['removed'])}",
        f"  features moved ({len(moves)}): {_listed(moves)}",
        f"  constraints added ({len(added)}): {_listed(added, '; ')}",
        f"  constraints removed ({len(removed)}): {_listed(removed, '; ')}",
    ]


@click.command("diff")
@click.argument("old", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.argument("new", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="print one JSON object")
@click.option(
    "--count", "count_unbounded", is_flag=True, help="count the products however long it takes"
)
@click.option(
    "--count-seconds",
    type=click.FloatRange(min=0.0),
    default=None,
    help="time bound for counting the products added and removed (past it: null and a "
    f"note); default: as long as reading and comparing took, at least {DEFAULT_COUNT_SECONDS:g} s",
)
def command(
    old: Path, new: Path, as_json: bool, count_unbounded: bool, count_seconds: float | None
) -> None:
    """Compare two versions of a feature model (.fm, .uvl, FeatureIDE .xml): is the edit a
    refactoring, a generalization, a specialization or arbitrary; how many products it
    added and removed, one example of each; features added, removed and moved;
    constraints added and removed. Exit 0 whatever the edit."""
    from spl.dsl.interop.formats import FORMATS, load_analysable_model

    if count_unbounded and count_seconds is not None:
        raise click.UsageError("give either --count or --count-seconds")
    if count_seconds is not None and count_seconds != count_seconds:  # NaN passes FloatRange
        raise click.BadParameter("nan is not a number of seconds", param_hint="--count-seconds")
    for path, role in ((old, "OLD"), (new, "NEW")):
        if path.suffix.lower() not in FORMATS:
            raise click.BadParameter(
                f"{path}: expected a .fm, .uvl or .xml feature model", param_hint=role
            )
    started = time.perf_counter()
    old_model = load_analysable_model(old)
    new_model = load_analysable_model(new)
    default = count_seconds is None and not count_unbounded
    report = diff_report(old_model, new_model, count_seconds, started if default else None)
    if as_json:
        click.echo(json.dumps(report, sort_keys=True))
    else:
        for line in text_report(old, new, report, not count_unbounded):
            click.echo(line)
