"""Loading and checking a product line leave its template model as parsed.

The language server relies on this: it keeps the System a .tsm text built and checks
the line again with it after an edit of the .rm or .fm (its workspace's
``spl.dsl.workspace.LastModels``), which is only right when nothing on the way
(the .rm builder, the line checks, the resolutions of their witness products and of the
listed products) changes the model.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.core.emf import copy_model
from spl.core.emf_compare import differences
from spl.dsl.tsm import language as tsm
from spl.dsl.workspace import LastModels, Workspace
from spl.pipeline import check_line, load_line

ROOT = Path(__file__).resolve().parents[2]


UNLOADABLE = {"bad_migration", "unloadable"}  # test lines made not to load


def _lines() -> list[Path]:
    folders = {p.parent for p in (ROOT / "product_lines").glob("*/*.rm")}
    folders |= {p.parent for p in (ROOT / "tests" / "models").rglob("*.rm")}
    return sorted(f for f in folders if len(list(f.glob("*.rm"))) == 1 and f.name not in UNLOADABLE)


@pytest.mark.parametrize("folder", _lines(), ids=lambda f: str(f.relative_to(ROOT)))
def test_checking_a_line_leaves_its_template_as_parsed(folder: Path) -> None:
    line = load_line(folder)
    before = copy_model(line.tsm)
    check_line(line)
    assert list(differences(before, line.tsm)) == []


def test_a_text_built_again_gives_the_same_model_only_in_a_workspace_keeping_models(
    tmp_path: Path,
) -> None:
    text = (ROOT / "product_lines" / "mapping3d" / "mapping.tsm").read_text(encoding="utf-8")
    name = str(tmp_path / "m.tsm")
    assert tsm.parse_text(text, name) is not tsm.parse_text(text, name)
    files = Workspace()  # the texts it refused, but no models kept
    assert tsm.parse_text(text, name, files) is not tsm.parse_text(text, name, files)
    workspace = Workspace(models=LastModels())
    checked = tsm.check_text(text, name, workspace=workspace)
    assert tsm.check_text(text, name, workspace=workspace) is checked  # checked once
    first = tsm.parse_text(text, name, workspace)
    assert tsm.parse_text(text, name, workspace) is first
    changed = tsm.parse_text(text + "\n", name, workspace)
    assert changed is not first and tsm.parse_text(text + "\n", name, workspace) is changed
    assert tsm.parse_text(text + "\n", name) is not changed
    # another workspace keeps its own models
    assert tsm.parse_text(text + "\n", name, Workspace(models=LastModels())) is not changed
