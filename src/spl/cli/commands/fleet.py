"""``spl fleet check|options|resolve FLEET.yaml``: robots sharing cloud node instances.

The analysis lives in :mod:`spl.resolver.fleets.fleet` (check), :mod:`spl.resolver.fleets.options`
(what a robot may still choose) and :mod:`spl.generators.fleet.bundle` (the fleet bundle); these
commands only read the fleet file and print.
"""

from __future__ import annotations

import json
from pathlib import Path

import click

from spl.cli.commands.resolve import namespace_option
from spl.core.diagnostics import Diagnostic, Location, ModelError

FLEET_FILE = click.Path(exists=True, dir_okay=False, path_type=Path)


@click.group("fleet")
def command() -> None:
    """Several robots of one product line sharing protected and public cloud nodes."""


@command.command("check")
@click.argument("fleet_file", type=FLEET_FILE)
def check(fleet_file: Path) -> None:
    """Resolve every robot and check that robots sharing a cloud instance ask the same of
    each of its nodes; conflicts are errors naming both robots and why they differ."""
    from spl.resolver.fleets.fleet import check_fleet, located, summary
    from spl.resolver.fleets.fleet_file import load_fleet

    result = check_fleet(load_fleet(fleet_file))
    if not result.ok:
        raise ModelError(located(result.diagnostics))
    _warn(result.diagnostics)
    for line in summary(result):
        click.echo(line)


@command.command("options")
@click.argument("fleet_file", type=FLEET_FILE)
@click.option("--robot", required=True, help="the robot to add (or to change)")
@click.option("--group", default=None, help="its group (default: its entry's, else 'default')")
@click.option(
    "--sharing",
    multiple=True,
    metavar="FEATURE=MODE",
    help="sharing mode private|protected|public for a feature (overrides the robot's entry)",
)
@click.option("--json", "as_json", is_flag=True, help="one JSON object")
def options(
    fleet_file: Path, robot: str, group: str | None, sharing: tuple[str, ...], as_json: bool
) -> None:
    """Which features ROBOT may still choose given the other robots as deployed: forced,
    forbidden and free, each with its reason; exit 1 when it cannot join at all."""
    from spl.resolver.fleets.fleet_file import NAME, load_fleet
    from spl.resolver.fleets.options import fleet_options
    from spl.resolver.resolution.product_selection import ProductSelection, apply_overrides

    for value, option in ((robot, "--robot"), (group, "--group")):
        if value is not None and not NAME.fullmatch(value):
            raise click.BadParameter(f"{value!r}: letters, digits, '_' and '-'", param_hint=option)
    overrides = apply_overrides(ProductSelection(robot, []), list(sharing), []).sharing
    fleet = load_fleet(fleet_file)
    result = fleet_options(fleet, robot, group, overrides)
    for problem in result.fleet_problems:
        click.echo(str(Diagnostic(problem.location, problem.message, "warning")), err=True)
    if as_json:
        click.echo(json.dumps(_as_dict(result), indent=2))
    else:
        for line in _lines(result):
            click.echo(line)
    if not result.joinable:
        entry = fleet.robot(robot)
        where = entry.location if entry is not None else Location(str(fleet_file), 1, 1)
        message = f"robot {robot} cannot join group {result.group}: " + "; ".join(result.blocking)
        if result.alternatives:
            message += f" (it could with sharing {' or '.join(result.alternatives)})"
        raise ModelError([Diagnostic(where, message)])


def _warn(diagnostics: list[Diagnostic]) -> None:
    """The warnings of a fleet that passed its check, on stderr: the robots' products'
    and the fleet's own."""
    from spl.resolver.fleets.fleet import located

    for warning in located([d for d in diagnostics if d.severity == "warning"]):
        click.echo(str(warning), err=True)


def _lines(result) -> list[str]:
    fixed = ", ".join(result.fixed_by) or "no robot"
    state = "can join" if result.joinable else "cannot join"
    lines = [
        f"robot {result.robot} in group {result.group}: {state} (shared nodes fixed by {fixed})"
    ]
    for option in result.options:
        if option.status != "free":
            lines.append(f"{option.status} {option.feature}: {'; '.join(option.reasons)}")
    free = [o.feature for o in result.options if o.status == "free"]
    if result.joinable:
        lines.append(f"free: {', '.join(free) or 'none'}")
        lines.append(f"in every product (feature model): {', '.join(result.core) or 'none'}")
        if result.dead:
            lines.append(f"in no product (feature model): {', '.join(result.dead)}")
    return lines


def _as_dict(result) -> dict:
    return {
        "robot": result.robot,
        "group": result.group,
        "joinable": result.joinable,
        "fixed_by": list(result.fixed_by),
        "blocking": list(result.blocking),
        "alternatives": list(result.alternatives),
        "features": {
            o.feature: {"status": o.status, "reasons": list(o.reasons)} for o in result.options
        },
        "core": list(result.core),
        "dead": list(result.dead),
    }


@command.command("resolve")
@click.argument("fleet_file", type=FLEET_FILE)
@click.option(
    "-o", "--out", type=click.Path(path_type=Path), help="bundle folder (default: build/FLEET)"
)
@namespace_option
def resolve(fleet_file: Path, out: Path | None, namespace: str | None) -> None:
    """Write one bundle for the fleet: each robot's own files, each shared cloud instance
    once, and fleet.json. Refused, writing nothing, when the fleet check fails."""
    from spl.generators.bundle.options import BundleOptions
    from spl.generators.bundle.writer import write_bundle
    from spl.generators.fleet.bundle import build_fleet_bundle
    from spl.pipeline import skip_warning
    from spl.resolver.fleets.deployment import deploy
    from spl.resolver.fleets.fleet import check_fleet, located, summary
    from spl.resolver.fleets.fleet_file import load_fleet

    fleet = load_fleet(fleet_file)
    result = check_fleet(fleet)
    if not result.ok:
        raise ModelError(located(result.diagnostics))
    _warn(result.diagnostics)
    bundle = build_fleet_bundle(deploy(result), BundleOptions(namespace=namespace))
    for path, reason in bundle.skipped.items():  # as spl resolve warns of a product's
        click.echo(str(skip_warning(path, reason)), err=True)
    out = out or Path("build") / fleet.name
    write_bundle(bundle.files, out)
    for line in summary(result):
        click.echo(line)
    click.echo(f"  wrote {len(bundle.files)} files to {out}")
