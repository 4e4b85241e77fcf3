"""The requests an editor makes of ``spl lsp`` and the notifications it sends: documents
opened, changed, saved and closed (each starts a debounced check), and definition,
references, hover, completion, outline and formatting, answered from the last parsed
models and the current text."""

from __future__ import annotations

import asyncio
import logging
import sys
from typing import Any

from lsprotocol import types

from spl.lsp import checking, completion, formatting, hover, outline
from spl.lsp.project import Document
from spl.lsp.server import SplLanguageServer, path_of, uri_of


def _path_and_offset(ls: SplLanguageServer, document: Any, position: Any) -> tuple[str, int]:
    path = path_of(document.uri)
    return path, ls.lines(path).offset(position)


def build_server() -> SplLanguageServer:
    """The server with every feature registered."""
    server = SplLanguageServer()

    @server.feature(types.EXIT)
    def exit_requested(ls: SplLanguageServer, *_: object) -> None:
        ls.exit_code = 0 if ls.stopping else 1  # the protocol's: exit without shutdown is 1

    @server.feature(types.INITIALIZED)
    def initialized(ls: SplLanguageServer, params: types.InitializedParams) -> None:
        ls.project.encoding = str(ls.workspace.position_encoding or "utf-16")

    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: SplLanguageServer, params: types.DidOpenTextDocumentParams) -> None:
        item = params.text_document
        path = path_of(item.uri)
        ls.project.documents[path] = Document(item.uri, path, item.version, item.text)
        ls.note_change(path)

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: SplLanguageServer, params: types.DidChangeTextDocumentParams) -> None:
        path = path_of(params.text_document.uri)
        document = ls.workspace.get_text_document(params.text_document.uri)
        ls.project.documents[path] = Document(
            document.uri, path, params.text_document.version, document.source
        )
        ls.note_change(path)

    @server.feature(types.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls: SplLanguageServer, params: types.DidSaveTextDocumentParams) -> None:
        ls.note_change(path_of(params.text_document.uri))  # files not open read it from disk

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: SplLanguageServer, params: types.DidCloseTextDocumentParams) -> None:
        path = path_of(params.text_document.uri)
        ls.project.documents.pop(path, None)
        ls.flush()  # a check no open document needs any more is forgotten
        ls.note_change(path)  # the saved file now stands for it

    @server.feature(types.TEXT_DOCUMENT_DEFINITION)
    async def definition(ls: SplLanguageServer, params: types.DefinitionParams) -> Any:
        await ls.wait_settled()
        path, offset = _path_and_offset(ls, params.text_document, params.position)
        occurrence, _ = ls.project.names_at(path, offset)
        if occurrence is None:
            return None
        return [ls.location(d) for d in occurrence.decls if d.file]

    @server.feature(types.TEXT_DOCUMENT_REFERENCES)
    async def references(ls: SplLanguageServer, params: types.ReferenceParams) -> Any:
        await ls.wait_settled()
        path, offset = _path_and_offset(ls, params.text_document, params.position)
        occurrence, _ = ls.project.names_at(path, offset)
        if occurrence is None:
            return None
        wanted = occurrence.decls
        found = []
        for file, other in ls.project.references(path, wanted):
            if other.declaration and not params.context.include_declaration:
                continue
            lines = ls.lines(file)
            found.append(
                types.Location(uri=uri_of(file), range=lines.range(other.start, other.end))
            )
        return found

    @server.feature(types.TEXT_DOCUMENT_HOVER)
    async def on_hover(ls: SplLanguageServer, params: types.HoverParams) -> Any:
        await ls.wait_settled()
        path, offset = _path_and_offset(ls, params.text_document, params.position)
        occurrence, index = ls.project.names_at(path, offset)
        if occurrence is None:
            return None
        text = hover.describe(occurrence.decls, index)
        if not text:
            return None
        return types.Hover(
            contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=text),
            range=ls.lines(path).range(occurrence.start, occurrence.end),
        )

    @server.feature(
        types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=["."])
    )
    async def on_completion(ls: SplLanguageServer, params: types.CompletionParams) -> Any:
        path, offset = _path_and_offset(ls, params.text_document, params.position)
        tsm, fm, _ = ls.project.family(path)
        if not any(ls.project.model(p) for p in (tsm, fm) if p):
            await ls.wait_settled()  # just opened: its models are being read
        index = ls.project.index(tsm, fm)
        items = completion.complete(path, ls.project.tokens(path), offset, index)
        return types.CompletionList(is_incomplete=False, items=items)

    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    async def document_symbol(ls: SplLanguageServer, params: types.DocumentSymbolParams) -> Any:
        await ls.wait_settled()
        path = path_of(params.text_document.uri)
        return outline.symbols(path, ls.project)

    @server.feature(types.TEXT_DOCUMENT_FORMATTING)
    async def on_formatting(ls: SplLanguageServer, params: types.DocumentFormattingParams) -> Any:
        path = path_of(params.text_document.uri)
        text = ls.project.text(path) or ""
        texts = {**ls.project.open_texts(), path: text}
        loop = asyncio.get_running_loop()
        parsed = await loop.run_in_executor(ls.checker, checking.check_file, path, ls.files(texts))
        formatted, reason = formatting.formatted(path, text, parsed.model)
        if formatted is None:
            ls.window_show_message(
                types.ShowMessageParams(type=types.MessageType.Warning, message=reason)
            )
            return None
        if formatted == text:
            return []
        lines = ls.lines(path)
        return [types.TextEdit(range=lines.range(0, len(text)), new_text=formatted)]

    @server.feature(types.SHUTDOWN)
    def shutdown(ls: SplLanguageServer, params: Any) -> None:
        ls.stopping = True  # no check starts after this
        if ls.check_task is not None:
            ls.check_task.cancel()
        ls.checker.shutdown(wait=False, cancel_futures=True)
        ls.analyses.shutdown()

    return server


def serve() -> None:
    """Serve one client over stdin and stdout until it says exit."""
    logging.basicConfig(level=logging.WARNING, format="spl lsp: %(levelname)s: %(message)s")
    server = build_server()
    server.start_io()
    if server.exit_code:  # pygls's own exit status is lost in an asyncio callback
        sys.exit(server.exit_code)
