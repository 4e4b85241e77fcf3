"""``spl smoke BUNDLE [--timeout S] [--json]``: start a bundle's ROS graph and compare it.

The rehearsal itself lives in :mod:`spl.smoke`; this module parses options, shows
progress and turns the result into output and an exit status: 0 when the live graph
matches the resolved model, 1 otherwise, 2 when ROS 1 is not installed.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click


@click.command("smoke")
@click.argument("bundle", type=click.Path(exists=True, file_okay=False, path_type=Path))
@click.option(
    "--timeout",
    type=click.FloatRange(min=1.0),
    default=30.0,
    show_default=True,
    help="seconds until everything still missing is reported",
)
@click.option("--json", "as_json", is_flag=True, help="one JSON object on stdout")
def command(bundle: Path, timeout: float, as_json: bool) -> None:
    """Rehearse BUNDLE (a folder written by spl resolve) with the real ROS 1: a private
    roscore per container, the bundle's own ros1/*.launch started by roslaunch with
    stand-in processes for the executables, endpoint relays along the model's bridges;
    then every node, topic, type, publisher, subscriber, service and parameter on each
    master is compared with the resolved model, and every subscriber must receive from
    each of its modelled sources and every client must be answered. A bundle with stores
    also runs its generated services and its generated ROS 1 writers and readers, and
    checks the data end to end (sent, stored, refined by the model's transform,
    received), through a kill and restart of a service."""
    from spl.core.lifetime import unwind_on_signals
    from spl.smoke.processes import RosMissing
    from spl.smoke.rehearsal import run_smoke
    from spl.smoke.report import text_report

    live = sys.stderr.isatty() and not as_json

    def progress(state) -> None:
        click.echo(f"\r{state.line()}\033[K", nl=False, err=True)

    unwind_on_signals(keyboard_interrupt=True)  # SIGTERM unwinds through the cleanup too
    try:
        result = run_smoke(bundle, timeout=timeout, progress=progress if live else None)
    except RosMissing as exc:
        click.echo(f"error: {exc}", err=True)
        sys.exit(2)
    except KeyboardInterrupt:
        click.echo("\nsmoke: interrupted; every process it started has been stopped", err=True)
        sys.exit(130)
    finally:
        if live:
            click.echo("\r\033[K", nl=False, err=True)
    for skipped in (result.skipped, result.actions_skipped):
        if skipped:
            click.echo(f"warning: {skipped}", err=True)
    if as_json:
        click.echo(json.dumps(result.as_dict(), indent=2))
    else:
        for line in text_report(result):
            click.echo(line)
    sys.exit(0 if result.passed else 1)
