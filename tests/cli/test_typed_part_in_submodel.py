"""A typed part in an imported submodel is refused where it is written, for every
command that reads the Boolean level of UVL only (docs/fm.md, "Imports")."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from spl.cli import main

MAIN = """namespace Main

imports
    Drive as d

features
    Main
        optional
            Lights
            d.Drive
"""

DRIVE = """namespace Drive

features
    Drive
        mandatory
            Integer speed
"""


@pytest.mark.parametrize(
    ("command", "said"),
    [
        (["products"], "this command reads the Boolean level of UVL only"),
        (["convert", "{main}", "{out}"], "spl convert to FeatureModel (.fm) cannot carry it"),
    ],
)
def test_the_refusal_names_the_submodel_file_and_line(
    tmp_path: Path, command: list[str], said: str
) -> None:
    (tmp_path / "main.uvl").write_text(MAIN, encoding="utf-8")
    (tmp_path / "Drive.uvl").write_text(DRIVE, encoding="utf-8")
    main_file, out = tmp_path / "main.uvl", tmp_path / "out.fm"
    argv = [a.format(main=main_file, out=out) for a in command]
    if len(argv) == 1:
        argv.append(str(main_file))
    result = CliRunner().invoke(main, argv)
    assert result.exit_code == 1, result.output
    assert f"{tmp_path / 'Drive.uvl'}:6:21: error: typed feature d.speed (Integer)" in (
        result.output
    ), result.output
    assert said in result.output
    assert not out.exists()
