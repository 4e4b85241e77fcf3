"""The editor and the terminal agree: for every model file of the shipped product lines
and of the bad-input models the tests keep (tests/models), the diagnostics ``spl lsp``
publishes are those ``spl check --json`` prints (same line, column, severity, code and
text; but the product-line checks' errors, which the editor shows as warnings on the
element); a feature model checked on its own (a UVL or FeatureIDE file, a .fm outside a
product line) gets those of ``spl check FILE``, its analysis included (a void model, the
dead features). Edited lines are checked from the editor's unsaved text against the same
edit saved in another folder.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import pytest_lsp
from click.testing import CliRunner
from lsprotocol import types
from pytest_lsp import LanguageClient

from spl.cli import main

from support.lsp_client import SERVER, change, close, diagnostics, open_file, start

ROOT = Path(__file__).resolve().parents[2]
MODEL_SUFFIXES = {".tsm", ".fm", ".rm"}
FEATURE_MODEL_SUFFIXES = {".uvl", ".xml"}
# product-line checks spl check reports as errors and the editor as warnings:
# an element no product activates, a reachable conflict, a product-dependent statement
LINE_CHECK_ERRORS = {"SPL010", "SPL012", "SPL016"}
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
    return by_file(json.loads(done.stdout))


def spl_check_file(path: Path) -> dict[Path, list[tuple]]:
    """``spl check FILE --json`` (in this process): its diagnostics by the file they are
    in (an imported UVL model's in its own)."""
    done = CliRunner().invoke(main, ["check", "--json", str(path)])
    assert done.exit_code in (0, 1), done.output
    return by_file(json.loads(done.stdout))


def by_file(report: dict) -> dict[Path, list[tuple]]:
    found: dict[Path, list[tuple]] = {}
    for d in report["diagnostics"]:
        key = (d["line"], d["col"], d["severity"], d["code"], d["message"])
        found.setdefault(Path(d["file"]).resolve(), []).append(key)
    return found


def analysed_alone(path: Path) -> bool:
    """A feature model ``spl check FILE`` analyses: any but a product line's .fm (in a
    folder holding exactly one .rm)."""
    if path.suffix in FEATURE_MODEL_SUFFIXES:
        return True
    return path.suffix == ".fm" and len(list(path.parent.glob("*.rm"))) != 1


def expected(folder: Path, files: list[Path]) -> dict[Path, list[tuple]]:
    """What the editor shows on each file of ``folder`` when all of ``files`` are open:
    the folder's check, and ``spl check FILE`` of each feature model checked alone."""
    checked = spl_check(folder) if any(p.suffix in MODEL_SUFFIXES for p in files) else {}
    for path in filter(analysed_alone, files):
        for file, found in spl_check_file(path).items():
            checked[file] = list(dict.fromkeys([*checked.get(file, []), *found]))
    return checked


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
    checked = expected(copy, files)
    for path in files:
        open_file(client, path, path.read_text(encoding="utf-8"))
    for path in files:
        text = path.read_text(encoding="utf-8")
        await agree(client, path, text, checked.get(path.resolve(), []))
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


DATA = ROOT / "tests" / "data"
TYPED = DATA / "uvl-parser" / "test_models"
ALONE = [  # a feature model opened alone, and what its analysis finds
    (DATA / "feature-models" / "axTLS.xml", "dead"),  # FeatureIDE, SAT
    (TYPED / "complex" / "Horcas2026_Pizza.uvl", "dead"),  # Type level, z3
    (TYPED / "arithmetic_level" / "aggregate_functions" / "aggregateFunctions03.uvl", "void"),
    (ROOT / "tests" / "models" / "analysis" / "void.fm", "void"),  # a .fm in no line, SAT
]


@pytest.mark.parametrize("source,finding", ALONE, ids=[a[0].name for a in ALONE])
async def test_a_feature_model_alone_shows_its_analysis(
    client: LanguageClient, source: Path, finding: str, tmp_path: Path
):
    """A void model's error at its root, or each dead feature's warning at its
    declaration: what spl check FILE prints, on the file."""
    path = tmp_path / source.name
    shutil.copyfile(source, path)
    wanted = spl_check_file(path)
    assert list(wanted) == [path.resolve()]
    found = wanted[path.resolve()]
    if finding == "void":
        assert [d[2] for d in found] == ["error"] and "has no product" in found[0][4]
    else:
        assert found and all(d[2] == "warning" and " is dead: " in d[4] for d in found)
    open_file(client, path)
    await agree(client, path, path.read_text(encoding="utf-8"), found)
    close(client, path)


async def test_a_dead_feature_of_an_imported_model_is_shown_in_its_file(
    client: LanguageClient, tmp_path: Path
):
    """The importing model's constraint kills a feature of the submodel: the warning is
    on the submodel's declaration, as spl check FILE places it, though only the importing
    file is open."""
    sub = tmp_path / "sub.uvl"
    sub.write_text("features\n\tSub\n\t\toptional\n\t\t\tA\n\t\t\tB\n", encoding="utf-8")
    root = tmp_path / "root.uvl"
    text = "imports\n\tsub as s\nfeatures\n\tR\n\t\toptional\n\t\t\ts.Sub\nconstraints\n\t!s.A\n"
    root.write_text(text, encoding="utf-8")
    wanted = spl_check_file(root)
    assert wanted == {
        sub.resolve(): [
            (4, 4, "warning", None, "feature s.A is dead: no product of the model contains it")
        ]
    }
    open_file(client, root, text)
    await agree(client, sub, sub.read_text(encoding="utf-8"), wanted[sub.resolve()])
    await agree(client, root, text, [])
    close(client, root)


async def test_an_edited_feature_model_shows_the_analysis_of_its_unsaved_text(
    client: LanguageClient, tmp_path: Path
):
    """Through edits: a constraint that kills two features, a syntax error (its error
    alone, the warnings of the text before gone), its fix, the constraint removed; each
    time what spl check FILE prints for the same text saved elsewhere."""
    model = "features\n\tCar\n\t\tmandatory\n\t\t\tEngine\n\t\toptional\n\t\t\tRadio\n"
    model += "\t\t\tNavigation\nconstraints\n\tNavigation => Radio\n"
    killed = model + "\t!Radio\n"
    edits = [model, killed, killed.replace("!Radio", "!Radio &"), killed, model]
    editor, saved = tmp_path / "editor" / "car.uvl", tmp_path / "saved" / "car.uvl"
    editor.parent.mkdir()
    saved.parent.mkdir()
    editor.write_text(model, encoding="utf-8")
    open_file(client, editor, model)
    shown = []
    for version, text in enumerate(edits, start=1):
        if version > 1:
            change(client, editor, text, version)
        saved.write_text(text, encoding="utf-8")
        wanted = spl_check_file(saved).get(saved.resolve(), [])
        shown.append(sorted({d[2] for d in wanted}))
        await agree(client, editor, text, wanted)
    assert shown == [[], ["warning"], ["error"], ["warning"], []]
    close(client, editor)
