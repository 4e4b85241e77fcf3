"""How long after a change ``spl lsp`` shows its diagnostics (docs/performance.md,
"Editor latency").

Starts the real server over stdio with pygls's client, opens a synthetic .tsm of N
nodes (the generator of bench/resolve_scaling.py) and measures, from the moment the
client sends it:

* open: the first diagnostics of the file;
* break: an edit that makes an error, until the error is shown (the file alone in its
  folder: its check is ``spl check FILE``), at the end of the file (a bridge naming an
  unknown container) and in the middle (a node subscribing an unknown topic), and two
  edits that leave a syntax error there (a bridge cut short at the end, a brace in
  the middle of a node);
* fix: the edit undone, until the error is gone;
* with ``--in-line``, valid edits of the .tsm (a node no product keeps, until the
  line's warning names it: in a container of its own at the end, and in the middle of
  a container the products keep) and, on the line's .rm, a break and fix of a
  ``require`` and a valid edit (a conflicting implementation, until SPL012 names it);

each break and fix ``--runs`` times in one session (what an editor does), reported as
min and median; and the same break/fix on the .rm of the shipped orchard line, whose
check is ``spl check FOLDER`` (parse plus the SAT product-line checks). The target is
under a second for a 10,000-node .tsm on the 2-core development machine.

With ``--feature-models FILE...`` (a UVL or FeatureIDE model opened alone, checked as
``spl check FILE``: read, then analysed, docs/editors.md), per file: open, until the
dead features' warnings are shown (the whole check); a syntax error (a dangling ``|``
in the constraints) and its fix; and a valid edit that the analysis alone sees, a
constraint ``!F`` that kills a live feature F, until the warning naming F shows and,
undone, clears (the model needs dead features: the open is timed until they show).
``bench/lsp_latency.py --sizes --feature-models tests/data/feature-models/automotive01.uvl``
measures the 18,616-feature model only.

The server runs without PYTHONDONTWRITEBYTECODE, as a user's install does (with
bytecode). textX words syntax errors, from an excerpt of the file that leaves out the
declarations before the one in error (``tsm_syntax_excerpt.error_excerpt``).

    python bench/lsp_latency.py [--sizes 1000 10000] [--runs 5] [--feature-models FILE...]
"""

from __future__ import annotations

import argparse
import asyncio
import os
import re
import shutil
import statistics
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
SYNTAX_BROKEN = "\nbridge Robot.\n"
EXTRA_NODE = "ExtraNode"  # the node a valid .tsm edit adds, which the line's warning names
MIDDLE_NODE = "MiddleNode"  # the same, added in the middle of a container
CONFLICT = "bench/conflict"  # the implementation a valid .rm edit gives, which SPL012 names


class Session:
    """One server and the diagnostics it published, with the time they arrived."""

    def __init__(self) -> None:
        self.client = LanguageClient("bench", "1")
        self.seen: dict[str, tuple[float, list[types.Diagnostic]]] = {}

        @self.client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def published(client: LanguageClient, params: types.PublishDiagnosticsParams) -> None:
            self.seen[params.uri] = (time.perf_counter(), list(params.diagnostics))

    async def start(self, root: Path) -> None:
        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        await self.client.start_io(sys.executable, "-m", "spl", "lsp", env=env)
        await self.client.initialize_async(
            types.InitializeParams(capabilities=types.ClientCapabilities(), root_uri=root.as_uri())
        )
        self.client.initialized(types.InitializedParams())

    async def stop(self) -> None:
        await self.client.shutdown_async(None)
        self.client.exit(None)
        await self.client.stop()

    async def until(
        self, uri: str, since: float, errors: bool, timeout: float = 600, about: str = ""
    ) -> float:
        """Seconds from ``since`` until ``uri`` shows (or no longer shows) an error, or,
        with ``about``, any finding whose message names it (``about`` ``*``: any finding)."""
        deadline = time.perf_counter() + timeout
        while time.perf_counter() < deadline:
            arrived, found = self.seen.get(uri, (0.0, []))
            if about == "*":
                shown = bool(found)
            elif about:
                shown = any(about in d.message for d in found)
            else:
                shown = any(d.severity == types.DiagnosticSeverity.Error for d in found)
            if arrived > since and shown == errors:
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


async def measure(
    path: Path, text: str, edits: list[tuple[int, str, str]], runs: int, opened: str = ""
) -> list:
    """Open, then each edit (at, inserted, about) made and undone ``runs`` times: the
    open time (until the file shows no error, or with ``opened`` a finding as ``about``
    selects it), and per edit the times the error took to show and to clear. An edit that
    leaves the model valid (``about`` not empty) is timed until the line's finding whose
    message names ``about`` shows and clears, each time with a new text (the run's count
    in place of ``{run}``): the line's checks must run on it."""
    session = Session()
    await session.start(path.parent)
    times: list = []
    try:
        uri, started = session.open(path, text)
        times.append(await session.until(uri, started, errors=opened != "", about=opened))
        version = 1
        for at, inserted, about in edits:
            shown, cleared = [], []
            for run in range(runs):
                change = inserted.replace("{run}", str(run))
                version += 1
                started = session.edit(uri, version, text, at, at, change)
                shown.append(await session.until(uri, started, True, about=about))
                edited = text[:at] + change + text[at:]
                version += 1
                started = session.edit(uri, version, edited, at, at + len(change), "")
                cleared.append(await session.until(uri, started, False, about=about))
            times.append((shown, cleared))
    finally:
        await session.stop()
    return times


def spread(times: list[float]) -> str:
    return f"{min(times):.2f} / {statistics.median(times):.2f}"


def live_feature(path: Path) -> str:
    """The last feature in file order that is neither core nor dead, as the file writes
    it: a constraint ``!F`` kills it and leaves the model satisfiable."""
    from spl.dsl.fm.language import all_features
    from spl.dsl.interop.formats import load_analysable_model
    from spl.dsl.interop.interchange import written_names
    from spl.resolver.analysis.formula import FeatureModelFormula

    model = load_analysable_model(path)
    with FeatureModelFormula(model) as formula:
        core, dead = formula.backbone()
    written = written_names(model)
    live = [f.name for f in all_features(model) if f.name not in core | dead]
    return written[live[-1]]


async def feature_model_rows(paths: list[Path], runs: int) -> None:
    """A feature model opened alone: read and analysed as ``spl check FILE``."""
    for source in paths:
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / source.name
            shutil.copyfile(source, path)
            text = path.read_text(encoding="utf-8")
            feature = live_feature(path)
            quoted = '"' + feature.replace('"', '\\"') + '"'
            if "\nconstraints" not in text:
                text += "\nconstraints\n"
            at = len(text.rstrip("\n"))
            edits = {
                "constraints, syntax": (at, "\n\t| ", ""),
                f"constraints, kills {feature}": (at, f"\n\t!{quoted} // {{run}}", feature),
            }
            opened, *found = await measure(path, text, list(edits.values()), runs, opened="*")
            for name, (shown, cleared) in zip(edits, found, strict=True):
                print(
                    f"| {source.name}, alone | {text.count(chr(10))} | {name} | {opened:.2f} "
                    f"| {spread(shown)} | {spread(cleared)} |",
                    flush=True,
                )


async def main_async(
    sizes: list[int], runs: int, in_line: bool, feature_models: list[Path]
) -> None:
    print(
        "| model | lines | edit | open (s) | error shown (s), min / median "
        "| error cleared (s), min / median |"
    )
    print("| --- | ---: | --- | ---: | ---: | ---: |")
    await feature_model_rows(feature_models, runs)
    if not sizes:
        return
    with tempfile.TemporaryDirectory() as tmp:
        for size in sizes:
            folder = Path(tmp) / f"n{size}"
            folder.mkdir()
            synthetic_line(folder, size)
            if not in_line:
                for other in ("synthetic.rm", "synthetic.fm"):  # the .tsm alone: spl check FILE
                    (folder / other).unlink()
            tsm = folder / "synthetic.tsm"
            text = tsm.read_text(encoding="utf-8")
            subscribed = [m.end() for m in re.finditer(r"subscribes \w+ <- ", text)]
            middle = subscribed[len(subscribed) // 2]
            edits = {
                "end": (len(text), BROKEN, ""),
                "middle": (middle, "x", ""),
                "end, syntax": (len(text), SYNTAX_BROKEN, ""),
                "middle, syntax": (middle, "{ ", ""),
            }
            if in_line:  # a valid change only the line's checks see: a node in no product
                extra = f"\ncloud container Extra {{\n    optional node {EXTRA_NODE} {{\n"
                extra += "        implementation pkg/extra\n    }\n}\n// {run}"
                edits["end, valid"] = (len(text), extra, EXTRA_NODE)
                # the same node in the middle of a container the line's products keep
                inside = text.index("\n    }\n", middle) + len("\n    }\n")
                node = f"    optional node {MIDDLE_NODE}{{run}} {{\n"
                node += "        implementation pkg/m\n    }\n"
                edits["middle, valid"] = (inside, node, MIDDLE_NODE)
            opened, *found = await measure(tsm, text, list(edits.values()), runs)
            lines = text.count(chr(10))
            where = "in its product line" if in_line else "alone"
            for name, (shown, cleared) in zip(edits, found, strict=True):
                print(
                    f"| .tsm, {size} nodes, {where} | {lines} | {name} | {opened:.2f} "
                    f"| {spread(shown)} | {spread(cleared)} |",
                    flush=True,
                )
            if in_line:  # the line's .rm: its .tsm is not built again (the workspace keeps it)
                rm = folder / "synthetic.rm"
                text = rm.read_text(encoding="utf-8")
                at = text.index("require ") + len("require ")
                # valid: a second implementation of a node, a conflict only the line's
                # checks find (SPL012)
                valid = (
                    f"\nwhen F7 selected {{\n    implementation RobotN0 = {CONFLICT}{{run}}\n}}\n"
                )
                rm_edits = {"require": (at, "Un", ""), "end, valid": (len(text), valid, CONFLICT)}
                opened, *found = await measure(rm, text, list(rm_edits.values()), runs)
                for name, (shown, cleared) in zip(rm_edits, found, strict=True):
                    print(
                        f"| synthetic.rm of the {size}-node line | {text.count(chr(10))} "
                        f"| {name} | {opened:.2f} | {spread(shown)} | {spread(cleared)} |",
                        flush=True,
                    )
        line = Path(tmp) / "orchard"
        shutil.copytree(ROOT / "product_lines" / "orchard", line)
        rm = line / "orchard.rm"
        text = rm.read_text(encoding="utf-8")
        at = text.index("require YieldMapper") + len("require ")
        opened, (shown, cleared) = await measure(rm, text, [(at, "Un", "")], runs)
        print(
            f"| orchard.rm (spl check FOLDER) | {text.count(chr(10))} | require | {opened:.2f} "
            f"| {spread(shown)} | {spread(cleared)} |"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[1000, 10000])
    parser.add_argument("--runs", type=int, default=5, help="breaks and fixes of each edit")
    parser.add_argument(
        "--in-line",
        action="store_true",
        help="the .tsm with the line's .fm and .rm beside it: checked as spl check FOLDER",
    )
    parser.add_argument(
        "--feature-models",
        type=Path,
        nargs="*",
        default=[],
        help="UVL files, each opened alone (spl check FILE: read and analysed)",
    )
    args = parser.parse_args()
    asyncio.run(main_async(args.sizes, args.runs, args.in_line, args.feature_models))


if __name__ == "__main__":
    main()
