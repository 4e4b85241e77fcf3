"""How long after a change ``spl lsp`` shows its diagnostics (issue 16 benchmark).

Starts the real server over stdio with pygls's client, opens a synthetic .tsm of N
nodes (the generator of bench/resolve_scaling.py) and measures, from the moment the
client sends it:

* open: the first diagnostics of the file;
* break: an edit at the end of the file that names an unknown container, until the
  error is shown (the file alone in its folder: its check is ``spl check FILE``);
* fix: the edit undone, until the error is gone;

and the same break/fix on the .rm of the shipped orchard line, whose check is
``spl check FOLDER`` (parse plus the SAT product-line checks). The target is under a
second for a 10,000-node .tsm on the 2-core development machine.

    python bench/lsp_latency.py [--sizes 1000 10000]
"""

from __future__ import annotations

import argparse
import asyncio
import shutil
import sys
import tempfile
import time
from pathlib import Path

from lsprotocol import types
from pygls.lsp.client import LanguageClient

sys.path.insert(0, str(Path(__file__).resolve().parent))
from resolve_scaling import synthetic_line

ROOT = Path(__file__).resolve().parents[1]
BROKEN = "\nbridge Robot.T0 -> Nowhere.T0\n"


class Session:
    """One server and the diagnostics it published, with the time they arrived."""

    def __init__(self) -> None:
        self.client = LanguageClient("bench", "1")
        self.seen: dict[str, tuple[float, list[types.Diagnostic]]] = {}

        @self.client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def published(client: LanguageClient, params: types.PublishDiagnosticsParams) -> None:
            self.seen[params.uri] = (time.perf_counter(), list(params.diagnostics))

    async def start(self, root: Path) -> None:
        await self.client.start_io(sys.executable, "-m", "spl", "lsp")
        await self.client.initialize_async(
            types.InitializeParams(capabilities=types.ClientCapabilities(), root_uri=root.as_uri())
        )
        self.client.initialized(types.InitializedParams())

    async def stop(self) -> None:
        await self.client.shutdown_async(None)
        self.client.exit(None)
        await self.client.stop()

    async def until(self, uri: str, since: float, errors: bool, timeout: float = 600) -> float:
        """Seconds from ``since`` until ``uri`` shows (or no longer shows) an error."""
        deadline = time.perf_counter() + timeout
        while time.perf_counter() < deadline:
            arrived, found = self.seen.get(uri, (0.0, []))
            if arrived > since and any(d.severity == 1 for d in found) == errors:
                return arrived - since
            await asyncio.sleep(0.005)
        raise TimeoutError(f"no diagnostics for {uri} after {timeout} s")

    def open(self, path: Path, text: str) -> tuple[str, float]:
        uri = path.resolve().as_uri()
        item = types.TextDocumentItem(uri=uri, language_id="spl", version=1, text=text)
        started = time.perf_counter()
        self.client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=item))
        return uri, started

    def edit(self, uri: str, version: int, text: str, start: int, end: int, new: str) -> float:
        """Replace characters ``start``..``end`` (one-line text positions) with ``new``."""

        def position(offset: int) -> types.Position:
            line = text.count("\n", 0, offset)
            return types.Position(line, offset - (text.rfind("\n", 0, offset) + 1))

        change = types.TextDocumentContentChangePartial(
            range=types.Range(position(start), position(end)), text=new
        )
        started = time.perf_counter()
        self.client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
                content_changes=[change],
            )
        )
        return started


async def measure(path: Path, text: str, broken_at: int, broken: str) -> tuple[float, ...]:
    session = Session()
    await session.start(path.parent)
    try:
        uri, started = session.open(path, text)
        opened = await session.until(uri, started, errors=False)
        started = session.edit(uri, 2, text, broken_at, broken_at, broken)
        shown = await session.until(uri, started, errors=True)
        edited = text[:broken_at] + broken + text[broken_at:]
        started = session.edit(uri, 3, edited, broken_at, broken_at + len(broken), "")
        cleared = await session.until(uri, started, errors=False)
    finally:
        await session.stop()
    return opened, shown, cleared


async def main_async(sizes: list[int]) -> None:
    print("| model | lines | open (s) | error shown (s) | error cleared (s) |")
    print("| --- | ---: | ---: | ---: | ---: |")
    with tempfile.TemporaryDirectory() as tmp:
        for size in sizes:
            folder = Path(tmp) / f"n{size}"
            folder.mkdir()
            synthetic_line(folder, size)
            for other in ("synthetic.rm", "synthetic.fm"):  # the .tsm alone: spl check FILE
                (folder / other).unlink()
            tsm = folder / "synthetic.tsm"
            text = tsm.read_text(encoding="utf-8")
            times = await measure(tsm, text, len(text), BROKEN)
            row = " | ".join(f"{t:.2f}" for t in times)
            print(f"| .tsm, {size} nodes | {text.count(chr(10))} | {row} |", flush=True)
        line = Path(tmp) / "orchard"
        shutil.copytree(ROOT / "product_lines" / "orchard", line)
        rm = line / "orchard.rm"
        text = rm.read_text(encoding="utf-8")
        at = text.index("require YieldMapper") + len("require ")
        times = await measure(rm, text, at, "Un")
        row = " | ".join(f"{t:.2f}" for t in times)
        print(f"| orchard.rm (spl check FOLDER) | {text.count(chr(10))} | {row} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000])
    asyncio.run(main_async(parser.parse_args().sizes))


if __name__ == "__main__":
    main()
