"""``spl render``: usage errors always; the shipped mapping line once its parsers exist."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner
from lxml import etree

from spl.cli import main

MAPPING = Path(__file__).resolve().parents[1] / "product_lines" / "mapping3d"


def run(*args: str):
    return CliRunner().invoke(main, ["render", *args])


def test_refuses_other_suffixes(tmp_path):
    result = run(str(MAPPING), "--what", "tsm", "-o", str(tmp_path / "out.pdf"))
    assert result.exit_code == 2 and ".svg or .png" in result.output
    assert not (tmp_path / "out.pdf").exists()


def test_product_view_needs_a_selection(tmp_path):
    result = run(str(MAPPING), "--what", "product", "-o", str(tmp_path / "out.svg"))
    assert result.exit_code == 2 and "--what product needs --features" in result.output


def test_renders_the_paper_product(tmp_path):
    pytest.importorskip("spl.dsl.tsm")
    pytest.importorskip("spl.dsl.fm")
    if not (MAPPING / "mapping.tsm").is_file() or not (MAPPING / "mapping.fm").is_file():
        pytest.skip("the mapping3d product line is not complete yet")
    out = tmp_path / "product.svg"
    result = run(str(MAPPING), "--features", "YouBot,Stereo,AdditionalPC,Room", "-o", str(out))
    assert result.exit_code == 0, result.output
    shown = {t.text for t in etree.parse(str(out)).iter("{*}text")}
    assert {"MapOptimizer", "StereoVision", "migrated from MappingCloud"} <= shown
    assert "DepthCamera" not in shown
    fm_out = tmp_path / "fm.png"
    result = run(
        str(MAPPING), "--what", "fm", "--features", "YouBot,Stereo,Room", "-o", str(fm_out)
    )
    assert result.exit_code == 0, result.output
    assert fm_out.read_bytes().startswith(b"\x89PNG")
