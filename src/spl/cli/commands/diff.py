"""``spl diff OLD NEW [--json] [--count | --count-seconds S]``: what an edit did to a
feature model (.fm, .uvl or FeatureIDE .xml, the two in any formats); ``spl diff
OLD_DIR NEW_DIR [--all | --sample t=N]`` or ``spl diff --rev REV DIR``: what it did to
a product line's products (:mod:`spl.validation.line_diff`).

The answer is a report, not a verdict: the exit status is 0 whatever the edit is, 1
only for a model that cannot be read. What it means is docs/evolution.md; the work is
:mod:`spl.resolver.analysis.operations.edit_classification`. As with ``spl analyze``,
the counts never make the command slow by default: they may take as long as reading
and comparing took, at least 1 s, and a count not finished by then is ``null``.
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import click

from spl.cli.commands.analyze import DEFAULT_COUNT_SECONDS
from spl.core.diagnostics import Diagnostic, ModelError, counted

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
@click.argument("paths", metavar="OLD NEW", nargs=-1, type=click.Path(path_type=Path))
@click.option(
    "--rev",
    metavar="REV",
    help="compare the line folder DIR with the same folder at git revision REV",
)
@click.option("--all", "all_products", is_flag=True, help="lines: also every valid product")
@click.option("--sample", metavar="t=N", help="lines: also a t-wise sample (t = 1, 2 or 3)")
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
    paths: tuple[Path, ...],
    rev: str | None,
    all_products: bool,
    sample: str | None,
    as_json: bool,
    count_unbounded: bool,
    count_seconds: float | None,
) -> None:
    """Compare two versions of a feature model (.fm, .uvl, FeatureIDE .xml): is the edit a
    refactoring, a generalization, a specialization or arbitrary; how many products it
    added and removed, one example of each; features added, removed and moved;
    constraints added and removed. Given two product line folders (or one and --rev),
    also the products added, removed and changed, and each changed bundle file with the
    element and model line that changed it. Exit 0 whatever the edit."""
    if count_unbounded and count_seconds is not None:
        raise click.UsageError("give either --count or --count-seconds")
    if count_seconds is not None and count_seconds != count_seconds:  # NaN passes FloatRange
        raise click.BadParameter("nan is not a number of seconds", param_hint="--count-seconds")
    counting = Counting(count_seconds, count_unbounded)
    if rev is not None or _lines(paths):
        _compare_lines(paths, rev, all_products, sample, as_json, counting)
        return
    if all_products or sample is not None:
        raise click.UsageError("--all and --sample compare product lines: give two folders")
    _compare_models(paths, as_json, counting)


@dataclass(frozen=True)
class Counting:
    """How long the products added and removed are counted (``--count-seconds S``,
    ``--count``: no bound; neither: as long as reading and comparing took)."""

    seconds: float | None
    unbounded: bool

    def bound(self, started: float) -> tuple[float | None, float | None]:
        """``diff_report``'s ``count_seconds`` and ``since``."""
        default = self.seconds is None and not self.unbounded
        return self.seconds, started if default else None


def _lines(paths: tuple[Path, ...]) -> bool:
    """Whether the paths name product line folders rather than feature-model files: one
    is a folder, or none has a feature model's suffix."""
    from spl.dsl.interop.formats import FORMATS

    return any(p.is_dir() for p in paths) or not any(p.suffix.lower() in FORMATS for p in paths)


def _compare_models(paths: tuple[Path, ...], as_json: bool, counting: Counting) -> None:
    from spl.dsl.interop.formats import FORMATS, load_analysable_model

    if len(paths) != 2:
        raise click.UsageError("give two feature models OLD NEW (or two line folders)")
    old, new = paths
    for path, role in ((old, "OLD"), (new, "NEW")):
        if not path.exists():
            raise click.BadParameter(f"{path}: no such file", param_hint=role)
        if path.suffix.lower() not in FORMATS:
            raise click.BadParameter(
                f"{path}: expected a .fm, .uvl or .xml feature model", param_hint=role
            )
    started = time.perf_counter()
    old_model = load_analysable_model(old)
    new_model = load_analysable_model(new)
    report = diff_report(old_model, new_model, *counting.bound(started))
    if as_json:
        click.echo(json.dumps(report, sort_keys=True))
    else:
        for line in text_report(old, new, report, not counting.unbounded):
            click.echo(line)


def _compare_lines(
    paths: tuple[Path, ...],
    rev: str | None,
    all_products: bool,
    sample: str | None,
    as_json: bool,
    counting: Counting,
) -> None:
    """``spl diff OLD_DIR NEW_DIR`` and ``spl diff --rev REV DIR`` (docs/evolution.md)."""
    from spl.cli.commands.products import parse_sample

    t = parse_sample(sample)
    if all_products and t is not None:
        raise click.UsageError("give one of --all and --sample")
    if rev is not None and len(paths) != 1:
        raise click.UsageError("with --rev REV give one line folder DIR")
    if rev is None and len(paths) != 2:
        raise click.UsageError("give two line folders OLD_DIR NEW_DIR (or --rev REV DIR)")
    for path in paths:
        if not path.is_dir():
            what = "not a folder" if path.exists() else "no such folder"
            # a path with no place in a file to point at (a folder's 0:0 says nothing)
            raise ModelError([Diagnostic(None, f"{path}: {what}: expected a product line folder")])
    mode = "all" if all_products else "sample" if t is not None else "listed"
    with tempfile.TemporaryDirectory(prefix="spl-diff-") as scratch:
        started = time.perf_counter()
        old, new, label = _versions(paths, rev, Path(scratch))
        report = line_report(old, new, mode, t or 2, counting.bound(started))
    report["old"], report["new"] = label, str(new.directory)
    if as_json:
        click.echo(json.dumps(report, sort_keys=True))
        return
    fm_lines = text_report(
        Path(label), new.directory, report["feature_model"], not counting.unbounded
    )
    for text in [*fm_lines, *products_report(report["products"])]:
        click.echo(text)


def _versions(paths: tuple[Path, ...], rev: str | None, scratch: Path) -> tuple[Any, Any, str]:
    """The old and new versions, loaded once each, and how the old one is named."""
    from spl import pipeline
    from spl.validation.bundle_changes import Version
    from spl.validation.versions import VersionProblem, load_revision

    if rev is None:
        old_dir, new_dir = paths
        before = Version(old_dir, pipeline.load_line(old_dir))
        return before, Version(new_dir, pipeline.load_line(new_dir)), str(old_dir)
    [directory] = paths
    try:
        old = load_revision(directory, rev, scratch)
    except VersionProblem as exc:
        click.echo(f"error: {exc}", err=True)
        sys.exit(1)
    if old is None:
        click.echo(
            f"error: {directory} is not in git revision {rev!r}: nothing to compare", err=True
        )
        sys.exit(1)
    return old, Version(directory, pipeline.load_line(directory)), f"{rev}:{directory}"


def line_report(
    old: Any, new: Any, mode: str, t: int, bound: tuple[float | None, float | None]
) -> dict:
    """The ``--json`` object of a line comparison: the feature model's edit as ``spl diff``
    of the two models reports it, and the products."""
    from spl.cli.commands.explain import explained
    from spl.generators.bundle.inputs import BundleMemo
    from spl.generators.bundle.options import BundleOptions
    from spl.validation.line_diff import compare_lines

    feature_model = diff_report(old.line.fm, new.line.fm, *bound)
    # the diagram's picture is drawn from architecture.dot, which is compared
    options = BundleOptions(render_diagrams=False)
    products = compare_lines(old, new, mode, t, explained, options, BundleMemo())
    return {"feature_model": feature_model, "products": products.as_json()}


def products_report(products: dict) -> list[str]:
    """The products part of the report for people."""
    changed, added, removed = products["changed"], products["added"], products["removed"]
    lines = [
        f"products: {len(changed)} changed, {products['unchanged']} unchanged, "
        f"{len(added)} added, {len(removed)} removed"
    ]
    for entry in changed:
        lines.append(f"  changed {_product(entry)}: {counted(len(entry['files']), 'file')}")
        paths: dict[str, list[str]] = {}  # each reason once, the files it changed under it
        for changed_file in entry["files"]:
            paths.setdefault(changed_file["reason"], []).append(changed_file["path"])
        for reason, files in paths.items():
            lines += [f"    {reason}", f"      {', '.join(files)}"]
    lines += [f"  added {_product(entry)}" for entry in added]
    lines += [f"  removed {_product(entry)}: {entry['reason']}" for entry in removed]
    return lines


def _product(entry: dict) -> str:
    name, features = entry["product"], entry["features"]
    return name if name == features else f"{name} ({features})"
