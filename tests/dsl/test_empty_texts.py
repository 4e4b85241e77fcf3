"""An empty text is read as the empty text, in every language.

textX, given an empty string, reads the file its name names instead: an editor's emptied
buffer of mapping.tsm was checked as the mapping.tsm saved on disk, and an empty unsaved
file was an internal error (FileNotFoundError)."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.fm import language as fm
from spl.dsl.rm import language as rm
from spl.dsl.tsm import language as tsm

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"


@pytest.mark.parametrize("saved", [True, False], ids=["file-on-disk", "no-file"])
def test_an_empty_tsm_is_an_empty_system(tmp_path: Path, saved: bool) -> None:
    name = str(MAPPING / "mapping.tsm") if saved else str(tmp_path / "new.tsm")
    for build in (tsm.parse_text, tsm.check_text):
        system = build("", name)
        assert system.name is None and list(system.containers) == []


@pytest.mark.parametrize(
    ("language", "file", "expected"),
    [(fm, "mapping.fm", "expected 'feature'"), (rm, "mapping.rm", "expected resolution")],
    ids=["fm", "rm"],
)
@pytest.mark.parametrize("saved", [True, False], ids=["file-on-disk", "no-file"])
def test_an_empty_fm_or_rm_is_a_syntax_error_at_its_start(
    tmp_path: Path, language, file: str, expected: str, saved: bool
) -> None:
    name = str(MAPPING / file) if saved else str(tmp_path / file)
    with pytest.raises(ModelError) as refused:
        language.parse_text("", name)
    assert str(refused.value.diagnostics[0]) == f"{name}:1:1: error: syntax error: {expected}"
