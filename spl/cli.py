"""The ``spl`` command line.

Each sub-command lives in its own module under :mod:`spl.commands` and exposes a
``command`` object; this module only assembles them and turns model errors into
located messages on stderr with exit status 1 (usage errors exit 2, as click does).
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import sys
from typing import Any

import click

from spl import __version__
from spl.diagnostics import ModelError


def report(diagnostics) -> None:
    for diagnostic in diagnostics:
        click.echo(str(diagnostic), err=True)


class SplGroup(click.Group):
    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except ModelError as exc:
            report(exc.diagnostics)
            ctx.exit(1)
        except (click.exceptions.Exit, click.exceptions.Abort, click.ClickException):
            raise
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


def _register_commands() -> None:
    import spl.commands as package

    for info in sorted(pkgutil.iter_modules(package.__path__), key=lambda i: i.name):
        module = importlib.import_module(f"{package.__name__}.{info.name}")
        command = getattr(module, "command", None)
        if isinstance(command, click.Command):
            main.add_command(command)


_register_commands()

if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
