"""Driving ``spl lsp`` over stdio with a real LSP client (pytest-lsp, built on pygls's
client) for the language-server tests: open, change and close documents and wait for
the diagnostics the server publishes."""

from __future__ import annotations

import asyncio
import sys
import time
from collections.abc import Callable
from pathlib import Path

from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

SERVER = ClientServerConfig(server_command=[sys.executable, "-m", "spl", "lsp"])
LANGUAGES = {".tsm": "spl-tsm", ".fm": "spl-fm", ".rm": "spl-rm", ".uvl": "uvl", ".xml": "xml"}


async def start(client: LanguageClient, root: Path) -> types.InitializeResult:
    """Initialize as VS Code does (UTF-16 positions); the result is kept on the client."""
    result = await client.initialize_session(
        types.InitializeParams(
            capabilities=client_capabilities("visual-studio-code"),
            root_uri=root.as_uri(),
        )
    )
    client.initialize_result = result  # type: ignore[attr-defined]
    return result


def uri(path: Path) -> str:
    return path.resolve().as_uri()


def open_file(client: LanguageClient, path: Path, text: str | None = None) -> str:
    text = path.read_text(encoding="utf-8") if text is None else text
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(
                uri=uri(path), language_id=LANGUAGES.get(path.suffix, "text"), version=1, text=text
            )
        )
    )
    return uri(path)


def change(client: LanguageClient, path: Path, text: str, version: int) -> None:
    """Replace the whole text of an open document (unsaved)."""
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri(path), version=version),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)],
        )
    )


def close(client: LanguageClient, *paths: Path) -> None:
    for path in paths:
        client.text_document_did_close(
            types.DidCloseTextDocumentParams(text_document=types.TextDocumentIdentifier(uri(path)))
        )


async def diagnostics(
    client: LanguageClient,
    path: Path,
    wanted: Callable[[list[types.Diagnostic]], bool],
    timeout: float = 60.0,
) -> list[types.Diagnostic]:
    """The diagnostics of ``path`` once ``wanted`` holds for them (fails after timeout)."""
    key = uri(path)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        found = client.diagnostics.get(key)
        if found is not None and wanted(list(found)):
            return list(found)
        await asyncio.sleep(0.05)
    raise AssertionError(f"no wanted diagnostics for {path}: last {client.diagnostics.get(key)}")


def position_of(text: str, needle: str, occurrence: int = 0, shift: int = 0) -> types.Position:
    """The LSP position (UTF-16) of the ``occurrence``-th ``needle`` in ``text``, moved
    ``shift`` characters into it."""
    start = -1
    for _ in range(occurrence + 1):
        start = text.index(needle, start + 1)
    offset = start + shift
    line = text.count("\n", 0, offset)
    before = text[text.rfind("\n", 0, offset) + 1 : offset]
    return types.Position(line, len(before.encode("utf-16-le")) // 2)
