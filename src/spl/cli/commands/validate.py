"""``spl validate DIR... [--all | --sample t=2] [--junit FILE] [--jobs N] [--strict]``: CI
validation.

``--changed-from OLD_DIR`` / ``--since REV``: a product whose bundle the old version of
its line derives alike is skipped, reported as such (docs/evolution.md, "In CI:
re-checking only what changed").

Every product of each line (its ``products/*.yaml``, plus all products or a t-wise
sample) is resolved and its whole bundle generated in memory and validated; one JUnit
test case per product, its warnings in its ``system-err`` and under its line. Exit 1
when any product fails; with ``--strict`` a product with warnings of its own fails too
(docs/ci.md, "A product's warnings").
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

import click


@click.command("validate")
@click.argument(
    "directories",
    metavar="DIR...",
    nargs=-1,
    required=True,
    type=click.Path(exists=True, file_okay=False, path_type=Path),
)
@click.option(
    "--all", "all_products", is_flag=True, help="also every valid product of the feature model"
)
@click.option(
    "--sample",
    metavar="t=N",
    help="also a t-wise covering array of the feature model (t = 1, 2 or 3)",
)
@click.option(
    "--junit",
    type=click.Path(dir_okay=False, path_type=Path),
    help="write a JUnit XML report (one test case per product)",
)
@click.option(
    "--jobs",
    "-j",
    type=click.IntRange(min=0),
    default=1,
    show_default=True,
    help="worker processes (0: one per CPU)",
)
@click.option(
    "--scheduler",
    metavar="ADDRESS",
    help="run the products on Dask: tcp://HOST:PORT (a running scheduler) or local:N "
    "(N workers on this machine); needs spl-robotics[cluster]",
)
@click.option(
    "--shard",
    metavar="K/N",
    help="run only part K of N of the products (CI matrices; merge the reports with "
    "spl merge-junit)",
)
@click.option(
    "--smoke",
    is_flag=True,
    help="also rehearse each valid bundle live with ROS 1 (as spl smoke does)",
)
@click.option(
    "--strict",
    is_flag=True,
    help="a product with warnings fails (an input nothing feeds, SPL045, an output it "
    "cannot have, ...); one about this machine (no Graphviz) fails none",
)
@click.option(
    "--diagrams",
    is_flag=True,
    help="also render each architecture.svg with Graphviz (one dot process per product)",
)
@click.option(
    "--changed-from",
    "changed_from",
    metavar="OLD_DIR",
    type=click.Path(exists=True, file_okay=False, path_type=Path),
    help="check only the products whose bundle differs from the one the line in OLD_DIR "
    "derives (one DIR); the others are reported skipped",
)
@click.option(
    "--since",
    metavar="REV",
    help="check only the products whose bundle differs from the one each DIR derived "
    "at git revision REV; the others are reported skipped",
)
def command(
    directories: tuple[Path, ...],
    all_products: bool,
    sample: str | None,
    junit: Path | None,
    jobs: int,
    scheduler: str | None,
    shard: str | None,
    smoke: bool,
    strict: bool,
    diagrams: bool,
    changed_from: Path | None,
    since: str | None,
) -> None:
    """Resolve every product of the product lines, generate and validate all of its
    artifacts, and report one test case per product (products/*.yaml always included).
    With --smoke every valid bundle is also started with the real ROS 1 and its live
    graph compared with the model (exit 2 when ROS 1 is not installed). A product's
    warning is printed under its line, counted and reported in its test case, and fails
    it only with --strict; one about this machine is said once and fails nothing."""
    from spl.cli.commands.products import parse_sample
    from spl.validation.junit import junit_xml
    from spl.validation.line import CaseChecks, Shard, load_lines, plan_cases, plan_digest
    from spl.validation.report import machine_notes, summary

    try:
        part = Shard.parse(shard) if shard is not None else None
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--shard") from None
    if scheduler is not None and jobs != 1:
        raise click.UsageError("give one of --jobs and --scheduler")
    if changed_from is not None and since is not None:
        raise click.UsageError("give one of --changed-from and --since")
    if changed_from is not None and len(directories) != 1:
        raise click.UsageError("--changed-from OLD_DIR compares one line DIR")
    if scheduler is not None and (changed_from is not None or since is not None):
        raise click.UsageError(
            "--changed-from and --since cannot be used with --scheduler: they validate on this "
            "machine (use --jobs N)"
        )
    # the workers of a cluster rehearse with their own ROS 1
    rehearse = _rehearsal() if smoke and scheduler is None else None
    if smoke:  # the rehearsals' processes are stopped on Ctrl-C and SIGTERM alike
        from spl.core.lifetime import unwind_on_signals

        unwind_on_signals(keyboard_interrupt=True)
    t = parse_sample(sample)
    if all_products and t is not None:
        raise click.UsageError("give one of --all and --sample")
    mode = "all" if all_products else "sample" if t is not None else "listed"
    jobs = jobs or os.cpu_count() or 1
    lines = load_lines(directories)
    scratch = tempfile.TemporaryDirectory(prefix="spl-validate-")  # the old versions' copies
    unchanged = _compare_with(lines, changed_from, since, Path(scratch.name))
    try:
        cases = plan_cases(lines, mode, t or 2)
    except ValueError as exc:  # too many combinations for t
        raise click.ClickException(str(exc)) from None
    plan = plan_digest(lines, cases)
    if part is not None:
        cases = part.of(cases)
    checks = CaseChecks(rehearse, diagrams, unchanged=unchanged)
    run = _runner(lines, cases, jobs, scheduler, checks, smoke)
    try:
        with scratch:
            results = _progress(run, len(cases), strict)
    except KeyboardInterrupt:  # workers and rehearsals have stopped what they started
        click.echo("\nvalidate: interrupted; no report written", err=True)
        sys.exit(130)
    if junit is not None:
        data = junit_xml(results, part, plan)
        junit.parent.mkdir(parents=True, exist_ok=True)
        partial = junit.with_name(junit.name + ".partial")
        partial.write_bytes(data)
        os.replace(partial, junit)
    for note in machine_notes(results):  # once for the run; each test case has it too
        click.echo(note, err=True)
    click.echo(summary(results))
    if not all(result.passed for result in results):
        sys.exit(1)


def _runner(lines, cases, jobs: int, scheduler: str | None, checks, smoke: bool):
    """What runs the cases, given where to report each result: this machine's processes,
    or the Dask cluster at ``scheduler``."""
    from spl.validation.line import run_cases

    if scheduler is None:
        return lambda on_result: run_cases(lines, cases, jobs, on_result=on_result, checks=checks)

    def on_cluster(on_result):
        from spl.validation.cluster import ClusterProblem, connect, run_on_cluster

        try:
            with connect(scheduler) as client:
                return run_on_cluster(client, lines, cases, checks, smoke, on_result)
        except ClusterProblem as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(2)

    return on_cluster


def _progress(run, total: int, strict: bool) -> list:
    """Run the cases with a progress bar on a terminal (then the lines of the products
    that failed or have warnings), one line per product otherwise; ``strict``: a product
    with warnings of its own fails."""
    from spl.validation.report import describe, strict as failing_on_warnings

    judged = failing_on_warnings if strict else list
    if sys.stderr.isatty():
        with click.progressbar(length=total, label="validating", file=sys.stderr) as bar:
            results = run(lambda _: bar.update(1))
        results = judged(results)
        for result in results:
            if not result.passed or result.product_warnings:
                for text in describe(result):
                    click.echo(text)
        return results

    def show(result) -> None:
        for text in describe(judged([result])[0]):
            click.echo(text)

    return judged(run(show))


def _rehearsal():
    """The live check of ``--smoke``, bound to the ROS 1 installation (found once)."""
    from functools import partial

    from spl.smoke.processes import RosMissing, find_ros
    from spl.smoke.rehearsal import rehearse_files

    try:
        return partial(rehearse_files, ros=find_ros())
    except RosMissing as exc:
        click.echo(f"error: {exc}", err=True)
        sys.exit(2)


def _compare_with(lines, changed_from: Path | None, since: str | None, scratch: Path) -> str:
    """Give each loaded line the old version its products are compared with; the reason
    an unchanged product is skipped. An old version that cannot be read or loaded skips
    nothing: said on stderr, and every product of that line is checked."""
    from spl import pipeline
    from spl.core.diagnostics import ModelError
    from spl.validation.bundle_changes import Version
    from spl.validation.versions import VersionProblem, load_revision

    if changed_from is None and since is None:
        return "bundle unchanged"
    for index, loaded in enumerate(lines):
        if loaded.line is None:
            continue
        try:
            if changed_from is not None:
                loaded.base = Version(changed_from, pipeline.load_line(changed_from))
            else:
                assert since is not None
                # a copy of its own: two lines may have one folder name
                loaded.base = load_revision(loaded.directory, since, scratch / str(index))
                if loaded.base is None:
                    click.echo(
                        f"note: {loaded.directory} is not in {since}: every product is checked",
                        err=True,
                    )
        except VersionProblem as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(1)
        except ModelError as exc:
            click.echo(
                f"note: the old version of {loaded.directory} does not load: every product "
                "is checked",
                err=True,
            )
            for diagnostic in exc.diagnostics:
                click.echo(f"  {diagnostic}", err=True)
        if loaded.base is not None:
            loaded.base.line.formula.backbone()  # computed once, inherited by every worker
    return (
        f"bundle unchanged since {since}"
        if since is not None
        else f"bundle unchanged from {changed_from}"
    )
