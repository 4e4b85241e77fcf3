"""The editor's workspace (docs/editors.md, "What the editor keeps"): what a check reads
and keeps is what the workspace passed to it holds, and nothing else. Its unsaved texts
stand in for the files for every reader a check runs (a line's .rm, the .tsm and .fm it
names, its listed products), its models are kept only by the workspace that built them,
and without one every file is read from disk and every model built afresh."""

from __future__ import annotations

import ast
import shutil
from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.fm import language as fm
from spl.dsl.rm import language as rm
from spl.dsl.tsm import language as tsm
from spl.dsl.workspace import LastModels, Workspace
from spl.pipeline import check_line, check_models, load_line

ROOT = Path(__file__).resolve().parents[2]
ORCHARD = ROOT / "product_lines" / "orchard"


@pytest.fixture
def orchard(tmp_path: Path) -> Path:
    folder = tmp_path / "orchard"
    shutil.copytree(ORCHARD, folder)
    return folder


def test_unsaved_texts_stand_in_for_the_files_a_line_reads(orchard: Path, monkeypatch) -> None:
    tsm_path, fm_path = orchard / "orchard.tsm", orchard / "orchard.fm"
    tsm_text = tsm_path.read_text(encoding="utf-8").replace(
        "robot container Scout", "robot container Rover"
    )
    fm_text = fm_path.read_text(encoding="utf-8") + "\n// unsaved\n"
    monkeypatch.chdir(orchard)  # a text given by a relative path stands for the same file
    workspace = Workspace().reading({"orchard.tsm": tsm_text, fm_path: fm_text})
    assert workspace.text(tsm_path) == tsm_text and workspace.text("orchard.fm") == fm_text
    system = tsm.parse_file(tsm_path, workspace)
    assert "Rover" in [c.name for c in system.containers]
    assert "Rover" not in [c.name for c in tsm.parse_file(tsm_path).containers]  # the disk's
    # the .rm reads the .tsm it names as the workspace has it: its names now lead nowhere
    with pytest.raises(ModelError) as refused:
        rm.load(orchard / "orchard.rm", workspace)
    assert any("Scout" in d.message for d in refused.value.diagnostics)
    assert rm.load(orchard / "orchard.rm").tsm is not None  # on disk, the line loads


def test_a_line_check_reads_its_listed_products_from_the_workspace(orchard: Path) -> None:
    product = orchard / "products" / "cloud_vacuum.yaml"
    unsaved = product.read_text(encoding="utf-8").replace("VacuumGripper", "NoSuchFeature")
    workspace = Workspace().reading({product: unsaved})
    codes = [d.code for d in check_line(load_line(orchard, workspace), workspace)]
    assert "SPL015" in codes
    assert "SPL015" not in [d.code for d in check_line(load_line(orchard))]


def test_models_are_kept_only_by_the_workspace_that_keeps_models(orchard: Path) -> None:
    """A workspace keeping models gives a text's model again; a view of it for single
    files (``of_files``) and a workspace without models build afresh, and share the
    refusals of the workspace they were made from."""
    path = orchard / "orchard.fm"
    text = path.read_text(encoding="utf-8")
    editor = Workspace(models=LastModels(), lines={})
    first = fm.parse_text(text, str(path), editor)
    assert fm.parse_text(text, str(path), editor) is first
    assert fm.parse_text(text, str(path), editor.of_files()) is not first
    assert fm.parse_text(text, str(path)) is not first
    assert editor.of_files().refused is editor.refused
    assert editor.reading({path: text}).models is editor.models
    assert editor.of_files().line_memory(orchard) is None
    assert editor.line_memory(orchard) is editor.line_memory(str(orchard) + "/")


def test_spl_check_of_a_folder_builds_a_refused_tsm_once(orchard: Path, monkeypatch) -> None:
    """``spl check FOLDER`` reads a .tsm through the line, then on its own: the second
    reading meets the first one's refusal (its own workspace), and reports it once."""
    path = orchard / "orchard.tsm"
    path.write_text(path.read_text(encoding="utf-8") + "bridge Harvester.Image -> Nowhere.Image\n")
    builds: list[str] = []
    real = tsm._parse
    monkeypatch.setattr(tsm, "_parse", lambda *a, **k: builds.append(a[1]) or real(*a, **k))
    _, found = check_models(orchard)
    assert [d.message for d in found] == ["unknown container Nowhere"]
    assert builds == [str(path)]
    builds.clear()
    check_models(orchard)  # a new check: nothing remembered from the last
    assert builds == [str(path)]


@pytest.mark.parametrize("layer", ["dsl", "resolver"])
def test_no_context_variables_in_the_languages_or_the_resolver(layer: str) -> None:
    """What a reader or a check depends on is in its parameters (docs/architecture.md)."""
    for module in sorted((ROOT / layer).rglob("*.py")):
        tree = ast.parse(module.read_text(encoding="utf-8"))
        imported = {
            alias.name
            for node in ast.walk(tree)
            if isinstance(node, ast.Import | ast.ImportFrom)
            for alias in node.names
        } | {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
        assert not imported & {"contextvars", "ContextVar"}, module
