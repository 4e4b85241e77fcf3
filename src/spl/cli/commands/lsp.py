"""``spl lsp``: serve the Language Server Protocol over stdio for .tsm, .fm and .rm
(and UVL / FeatureIDE .xml feature models) so an editor shows ``spl check``'s
findings as you type, with navigation, completion, hover, outline and formatting."""

from __future__ import annotations

import click


@click.command("lsp")
@click.option(
    "--stdio", is_flag=True, help="Talk over stdin/stdout (the default; editors pass it)."
)
def command(stdio: bool) -> None:
    """Start the language server on stdin/stdout (for an editor to run)."""
    from spl.lsp.requests import serve

    serve()
