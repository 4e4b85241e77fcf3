"""``spl render`` on the launch test product line (tests/models/launch)."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner
from lxml import etree

from spl.cli import main

FLEET = Path(__file__).parents[1] / "models" / "launch"
MAPPING = Path(__file__).resolve().parents[2] / "product_lines" / "mapping3d"


def run(*args: str):
    return CliRunner().invoke(main, ["render", *args])


def test_refuses_other_suffixes(tmp_path):
    result = run(str(FLEET), "--what", "tsm", "-o", str(tmp_path / "out.pdf"))
    assert result.exit_code == 2 and ".svg, .png or .dot" in result.output
    assert not (tmp_path / "out.pdf").exists()


def test_product_view_needs_a_selection(tmp_path):
    result = run(str(FLEET), "--what", "product", "-o", str(tmp_path / "out.svg"))
    assert result.exit_code == 2 and "--what product needs --features" in result.output


def test_renders_product_template_and_feature_model(tmp_path):
    out = tmp_path / "product.svg"
    result = run(str(FLEET), "--features", "CloudMapping,OnboardSlam", "-o", str(out))
    assert result.exit_code == 0, result.output
    shown = {t.text for t in etree.parse(str(out)).iter("{*}text")}
    assert {"Slam", "MapSaver", "migrated from Mapping"} <= shown

    template = tmp_path / "template.svg"
    assert run(str(FLEET), "-o", str(template)).exit_code == 0
    shown = {t.text for t in etree.parse(str(template)).iter("{*}text")}
    assert {"Slam", "MapSaver", "Lidar"} <= shown and "migrated from Mapping" not in shown

    fm_out = tmp_path / "fm.png"
    result = run(str(FLEET), "--what", "fm", "--features", "CloudMapping", "-o", str(fm_out))
    assert result.exit_code == 0, result.output
    assert fm_out.read_bytes().startswith(b"\x89PNG")


def test_model_errors_are_located(tmp_path):
    result = run(str(FLEET), "--features", "NoSuchFeature", "-o", str(tmp_path / "x.svg"))
    assert result.exit_code == 1
    assert "NoSuchFeature" in result.output
    assert not (tmp_path / "x.svg").exists()


def test_rendered_and_converted_files_get_the_umasks_mode(tmp_path) -> None:
    # were 0600 (mkstemp's) for spl render, and a fixed 0644 for spl convert
    import os
    import stat

    previous = os.umask(0o027)
    try:
        out = tmp_path / "t.dot"
        result = run(str(MAPPING), "--what", "tsm", "-o", str(out))
        assert result.exit_code == 0, result.output
        converted = tmp_path / "m.uvl"
        result = CliRunner().invoke(main, ["convert", str(MAPPING / "mapping.fm"), str(converted)])
        assert result.exit_code == 0, result.output
    finally:
        os.umask(previous)
    assert stat.S_IMODE(out.stat().st_mode) == stat.S_IMODE(converted.stat().st_mode) == 0o640
