"""The ``spl`` command line.

Each sub-command lives in its own module under :mod:`spl.cli.commands` and exposes a
``command`` object; this module only assembles them and turns model errors into
located messages on stderr with exit status 1 (usage errors exit 2, as click does).

Commands are imported when they run, not when ``spl`` starts: the module of a command
is named like the command, so ``spl check`` imports ``spl.cli.commands.check`` (and what
it needs) and nothing else; only ``spl --help`` imports them all. Every start pays for
click alone (``bench/cli_start.py`` measures it).
"""

from __future__ import annotations

import atexit
import gc
import importlib
import os
import sys
from pathlib import Path
from typing import Any

import click

from spl import __version__
from spl.core.diagnostics import ModelError


def _no_collection_at_exit() -> None:
    """The process is ending and the OS takes its memory back: a last cyclic collection
    would walk every object of the models a command read (some two million for a
    10,000-node .tsm: seconds) only to free them. Runs after the other exit handlers."""
    gc.freeze()


atexit.register(_no_collection_at_exit)


def report(diagnostics) -> None:
    for diagnostic in diagnostics:
        click.echo(str(diagnostic), err=True)


def _command_modules() -> list[str]:
    """Names of the modules of spl.cli.commands (a listing of its folder: no import)."""
    folder = Path(__file__).resolve().parent / "commands"
    return sorted(
        entry.name[:-3]
        for entry in os.scandir(folder)
        if entry.name.endswith(".py") and not entry.name.startswith("_")
    )


def _load_command(module_name: str) -> click.Command | None:
    module = importlib.import_module(f"spl.cli.commands.{module_name}")
    command = getattr(module, "command", None)
    return command if isinstance(command, click.Command) else None


class SplGroup(click.Group):
    def list_commands(self, ctx: click.Context) -> list[str]:
        names = set(super().list_commands(ctx))
        for module_name in _command_modules():
            command = _load_command(module_name)  # listing means showing their help
            if command is not None and command.name:
                names.add(command.name)
        return sorted(names)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        known = super().get_command(ctx, cmd_name)
        if known is not None:
            return known
        modules = _command_modules()
        # the module named like the command first (a Python keyword gets a trailing _:
        # `spl import` is import_.py); any other only if it is not there
        wanted = cmd_name.replace("-", "_")
        for module_name in sorted(modules, key=lambda m: m.rstrip("_") != wanted):
            command = _load_command(module_name)
            if command is not None and command.name == cmd_name:
                self.add_command(command)
                return command
        return None

    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except ModelError as exc:
            report(exc.diagnostics)
            ctx.exit(1)
        except (click.exceptions.Exit, click.exceptions.Abort, click.ClickException):
            raise
        except BrokenPipeError:
            # the reader left (`spl products LINE | head`): what it wanted was written;
            # stdout goes to /dev/null so Python's flush at exit does not fail again
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            ctx.exit(141)  # 128 + SIGPIPE, as a shell tool killed by the signal
        except OSError as exc:
            name = getattr(exc, "filename", None)
            where = f"{name}: " if name else ""
            click.echo(f"{where}error: {exc.strerror or exc}", err=True)
            ctx.exit(1)
        except Exception as exc:  # an spl bug: say so plainly; SPL_DEBUG=1 shows the trace
            if os.environ.get("SPL_DEBUG"):
                raise
            click.echo(
                f"error: internal error in spl {__version__}: {type(exc).__name__}: {exc} "
                "(run with SPL_DEBUG=1 for a traceback and report it)",
                err=True,
            )
            ctx.exit(3)


@click.group(cls=SplGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="spl")
def main() -> None:
    """Model-driven software product lines for cloud robotics.

    Describe a family of ROS/Rapyuta applications once (.tsm, .fm, .rm), pick
    features, and get launch files, Rapyuta configurations and cloud services.
    """


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
