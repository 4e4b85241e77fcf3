"""``spl check FILE_OR_DIR``: parse and check models, print a one-line summary each."""

from __future__ import annotations

import importlib
from pathlib import Path

import click

from spl.diagnostics import Diagnostic, Location, ModelError

# The language module for each model file kind. Each offers ``parse_file(path)`` (raising
# ModelError with every problem found) and ``summary(model) -> str``.
LANGUAGES = {".tsm": "spl.dsl.tsm", ".fm": "spl.dsl.fm", ".rm": "spl.dsl.rm"}


def check_file(path: Path) -> str:
    module_name = LANGUAGES.get(path.suffix)
    if module_name is None:
        known = ", ".join(sorted(LANGUAGES))
        raise ModelError(
            [Diagnostic(Location(str(path), 1, 1), f"unknown model kind (expected {known})")]
        )
    language = importlib.import_module(module_name)
    model = language.parse_file(path)
    return f"{path}: ok: {language.summary(model)}"


def model_files(directory: Path) -> list[Path]:
    return sorted(p for p in directory.iterdir() if p.suffix in LANGUAGES and p.is_file())


@click.command("check")
@click.argument("target", type=click.Path(exists=True, path_type=Path))
def command(target: Path) -> None:
    """Parse and check a model file (.tsm, .fm, .rm) or a product-line folder.

    Every problem is printed as FILE:LINE:COL: error: MESSAGE; the exit status is 1
    when any error was found.
    """
    files = model_files(target) if target.is_dir() else [target]
    if not files:
        raise click.UsageError(f"{target} holds no .tsm, .fm or .rm file")
    problems: list[Diagnostic] = []
    for path in files:
        try:
            click.echo(check_file(path))
        except ModelError as exc:
            problems.extend(exc.diagnostics)
    if problems:
        raise ModelError(problems)
