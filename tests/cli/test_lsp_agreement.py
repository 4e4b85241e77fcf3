"""The editor and the terminal agree: for every model file of the shipped product lines
and of the bad-input models the tests keep (tests/models), the diagnostics ``spl lsp``
publishes are those ``spl check --json`` prints (same line, column, severity, code and
text; but the product-line checks' errors, which the editor shows as warnings on the
element), and for UVL and FeatureIDE files those ``spl analyze`` prints. Edited lines
are checked from the editor's unsaved text against the same edit saved in another
folder.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from support.lsp_client import SERVER, change, close, diagnostics, open_file, start

ROOT = Path(__file__).resolve().parents[2]
MODEL_SUFFIXES = {".tsm", ".fm", ".rm"}
FEATURE_MODEL_SUFFIXES = {".uvl", ".xml"}
# product-line checks spl check reports as errors and the editor as warnings:
# an element no product activates, a reachable conflict, a product-dependent statement
LINE_CHECK_ERRORS = {"SPL010", "SPL012", "SPL016"}
LOCATED = re.compile(r"^(.*?):(\d+):(\d+): (error|warning|info): (.*?)(?: \[(SPL\d+)\])?$")
pytestmark = pytest.mark.asyncio(loop_scope="module")


def folders() -> list[Path]:
    found = sorted((ROOT / "product_lines").iterdir())
    found += sorted({p.parent for p in (ROOT / "tests" / "models").rglob("*") if p.is_file()})
    return [
        f
        for f in found
        if f.is_dir()
        and any(p.suffix in MODEL_SUFFIXES | FEATURE_MODEL_SUFFIXES for p in f.iterdir())
    ]


@pytest_lsp.fixture(config=SERVER, scope="module")
async def client(lsp_client: LanguageClient, tmp_path_factory):
    await start(lsp_client, tmp_path_factory.getbasetemp())
    yield
    await lsp_client.shutdown_session()


def spl_check(folder: Path) -> dict[Path, list[tuple]]:
    """``spl check FOLDER --json``: its diagnostics by file (the folder's files each
    checked alone when the folder is not a product line, as ``spl check FILE`` does)."""
    done = subprocess.run(
        [sys.executable, "-m", "spl", "check", "--json", str(folder)],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    found: dict[Path, list[tuple]] = {}
    for d in json.loads(done.stdout)["diagnostics"]:
        key = (d["line"], d["col"], d["severity"], d["code"], d["message"])
        found.setdefault(Path(d["file"]).resolve(), []).append(key)
    return found


def spl_analyze(path: Path) -> list[tuple]:
    """The located findings ``spl analyze FILE`` prints for a UVL or FeatureIDE file."""
    done = subprocess.run(
        [sys.executable, "-m", "spl", "analyze", "--count-seconds", "0", str(path)],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    found = []
    for line in done.stderr.splitlines():
        match = LOCATED.match(line)
        if match:
            _, row, col, severity, message, code = match.groups()
            found.append((int(row), int(col), severity, code, message))
    return found


def as_spl(diagnostic: types.Diagnostic, text: str) -> tuple:
    line = diagnostic.range.start.line
    lines = text.split("\n")
    prefix = lines[line].encode("utf-16-le")[: 2 * diagnostic.range.start.character]
    severity = {1: "error", 2: "warning", 3: "info"}[diagnostic.severity]
    column = len(prefix.decode("utf-16-le")) + 1
    return (line + 1, column, severity, diagnostic.code, diagnostic.message)


def comparable(found: list[tuple], editor: bool) -> list[tuple]:
    """Diagnostics in a comparable order, a product-line check's severity set aside
    after checking it is the one its side gives it (editor: warning, spl check: error)."""
    result = []
    for line, col, severity, code, message in found:
        if code in LINE_CHECK_ERRORS:
            if severity != ("warning" if editor else "error"):
                return [("unexpected severity", line, col, severity, code, message)]
            severity = "a product-line finding"
        result.append((line, col, severity, code, message))
    return sorted(result)


async def agree(client: LanguageClient, path: Path, text: str, wanted: list[tuple]) -> None:
    expected = comparable(wanted, editor=False)

    def same(found: list[types.Diagnostic]) -> bool:
        return comparable([as_spl(d, text) for d in found], editor=True) == expected

    try:
        await diagnostics(client, path, same, timeout=60)
    except AssertionError:
        shown = [as_spl(d, text) for d in client.diagnostics.get(path.resolve().as_uri(), [])]
        assert comparable(shown, editor=True) == expected, path


@pytest.mark.parametrize("folder", folders(), ids=lambda f: str(f.relative_to(ROOT)))
async def test_every_file_gets_the_diagnostics_of_spl_check(
    client: LanguageClient, folder: Path, tmp_path: Path
):
    copy = tmp_path / folder.name
    shutil.copytree(folder, copy)
    files = sorted(p for p in copy.iterdir() if p.suffix in MODEL_SUFFIXES | FEATURE_MODEL_SUFFIXES)
    checked = spl_check(copy) if any(p.suffix in MODEL_SUFFIXES for p in files) else {}
    for path in files:
        open_file(client, path, path.read_text(encoding="utf-8"))
    for path in files:
        text = path.read_text(encoding="utf-8")
        if path.suffix in MODEL_SUFFIXES:
            wanted = checked.get(path.resolve(), [])
        else:
            wanted = spl_analyze(path)
        await agree(client, path, text, wanted)
    close(client, *files)


EDITS = [  # (file, old, new): slips a user makes while typing
    ("mapping3d/mapping.rm", "require RGBCameraL", "require RGBCamera"),
    ("mapping3d/mapping.rm", "migrate MapOptimizer to Robot", "migrate MapOptimizer to Robot2"),
    ("mapping3d/mapping.tsm", "node StereoVision", "node Stereo_Vision"),
    ("mapping3d/mapping.fm", "Roomba excludes AdditionalPC", "Roomba excludes AdditionalPCs"),
    ("orchard/orchard.rm", "when SoftGripper selected {", "when VacuumGripper selected {"),
    (
        "orchard/orchard.rm",
        "connect YieldMapper.image to topic ScoutImage",
        "connect YieldMapper.image to topic",
    ),
    (
        "orchard/orchard.tsm",
        "    topic Odom   : nav_msgs/Odometry",
        "    topic Odom   : nav_msgs/Odometry   topic",
    ),
    ("data_acquisition/data.tsm", "every 5 s", "every 5"),
]


@pytest.mark.parametrize("file,old,new", EDITS, ids=[f"{e[0]}:{e[2]}" for e in EDITS])
async def test_unsaved_edit_gets_the_diagnostics_of_the_saved_edit(
    client: LanguageClient, file: str, old: str, new: str, tmp_path: Path
):
    source = ROOT / "product_lines" / file
    editor, saved = tmp_path / "editor", tmp_path / "saved"
    shutil.copytree(source.parent, editor / source.parent.name)
    shutil.copytree(source.parent, saved / source.parent.name)
    text = source.read_text(encoding="utf-8")
    assert old in text
    edited = text.replace(old, new, 1)
    (saved / file).write_text(edited, encoding="utf-8")
    wanted = spl_check(saved / source.parent.name)
    siblings = sorted(
        p for p in (editor / source.parent.name).iterdir() if p.suffix in MODEL_SUFFIXES
    )
    for path in siblings:
        open_file(client, path)
    change(client, editor / file, edited, 2)
    for path in siblings:
        expected = [
            (*d[:4], d[4].replace(str(saved.resolve()), str(editor.resolve())))
            for d in wanted.get((saved / path.relative_to(editor)).resolve(), [])
        ]
        shown = edited if path == editor / file else path.read_text(encoding="utf-8")
        await agree(client, path, shown, expected)
    assert any(wanted.values())  # every edit is a mistake spl reports
    close(client, *siblings)


async def test_a_dead_resolution_element_is_a_warning_on_its_line(
    client: LanguageClient, tmp_path: Path
):
    """spl check says error (exit 1), the editor a warning at the same place and text."""
    copy = tmp_path / "broken"
    shutil.copytree(ROOT / "tests" / "models" / "line_checks" / "broken", copy)
    rm = copy / "broken.rm"
    text = rm.read_text(encoding="utf-8")
    assert text.split("\n")[5].startswith("when Gripper selected")
    dead = [d for d in spl_check(copy)[rm.resolve()] if d[3] == "SPL010"]
    assert dead and all(d[2] == "error" for d in dead)
    open_file(client, rm, text)

    def dead_shown(found: list[types.Diagnostic]) -> bool:
        return any(d.code == "SPL010" for d in found)

    shown = await diagnostics(client, rm, dead_shown, timeout=60)
    on_line = [d for d in shown if d.code == "SPL010" and d.range.start.line == 5]
    assert on_line and all(d.severity == types.DiagnosticSeverity.Warning for d in on_line)
    assert {as_spl(d, text)[:2] + as_spl(d, text)[3:] for d in shown if d.code == "SPL010"} == {
        d[:2] + d[3:] for d in dead
    }
    close(client, rm)
