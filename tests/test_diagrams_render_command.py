"""``spl render`` on the launch test product line (tests/models/launch)."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner
from lxml import etree

from spl.cli import main

FLEET = Path(__file__).parent / "models" / "launch"


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
