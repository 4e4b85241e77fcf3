"""The line-wide dataflow check (docs/semantics.md F8) against brute force: on the
warehouse test line, every shipped line, the broken test line, random resolution models
of the farm line (statements that connect and bridge) and random templates
(tests/support/random_lines.py: optional nodes, migrations, bridges), every product is
resolved, and ``spl check`` must report exactly the inputs some product leaves unfed,
each with a witness product that resolves with that warning."""

from __future__ import annotations

import random
import re
import shutil
import tempfile
from functools import cache
from pathlib import Path

import pytest
from hypothesis import assume, given, settings

from spl.core.diagnostics import ModelError
from spl.dsl.interop import formats as fm_formats
from spl.dsl.tsm import language as tsm
from spl.resolver.line_checks import check_product_line
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.explanation import explanation
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.farm_statements import MODELS as FARM, resolution_model
from support.hypothesis_budget import examples
from support.random_lines import LineSpec, line_specs, write_line
from support.unfed_products import assert_check_agrees, gaps, unfed_somewhere, witness_of

ROOT = Path(__file__).resolve().parents[2]
WAREHOUSE = ROOT / "tests" / "models" / "line_checks" / "warehouse"
SHIPPED = sorted(p.name for p in (ROOT / "product_lines").iterdir() if p.is_dir())


def test_the_warehouse_localizer_is_unfed_in_the_camera_products():
    line = load_product_line(WAREHOUSE)
    found = [d for d in check_product_line(line) if d.code in ("SPL045", "SPL046")]
    assert [(Path(d.location.file).name, d.location.line, d.code) for d in found] == [
        ("warehouse.tsm", 28, "SPL045"),  # Localizer.scan; Localizer.odom is fed externally
        ("warehouse.tsm", 53, "SPL046"),  # Detector.classify
    ]
    scan, classify = found
    assert scan.severity == "warning"
    assert scan.message.startswith(
        "Localizer.scan subscribes Amr.Scan, which no node of the product publishes, in the "
        "product CameraSensing, Sensing, Warehouse; its feeder Lidar.scan is left out: "
        "optional node Lidar is kept only by 'when LidarSensing selected' ("
    )
    assert "its server Classifier.classify is left out" in classify.message
    assert "Detection" in witness_of(classify)
    # the witness resolves with the very warning, at the same place
    assert (str(scan.location.file), 28, 20, "SPL045") in gaps(line, witness_of(scan))


def explanation_of(line, name: str, features: str) -> str:
    resolution = resolve(line, selection_from_list(features))
    lines = explanation(line.tsm, resolution.product, resolution.trace, name)
    assert lines is not None
    return "\n".join(lines)


def test_an_input_fed_from_outside_is_silent_everywhere_and_explained(tmp_path):
    """Localizer.odom says what feeds it (``external "..."``): no product warns, and
    neither does the check; without the annotation every product does."""
    line = load_product_line(WAREHOUSE)
    odom = (str(WAREHOUSE / "warehouse.tsm"), 29, 20)
    assert all(place[:3] != odom for place in unfed_somewhere(line))
    explained = explanation_of(line, "Localizer.odom", "CameraSensing")
    assert "fed from outside the architecture: wheel odometry of the base driver" in explained
    assert "(SPL045)" not in explained
    scan = explanation_of(line, "Localizer.scan", "CameraSensing")
    assert "fed by no flow of this product (SPL045)" in scan

    for name in ("warehouse.fm", "warehouse.rm"):
        shutil.copy(WAREHOUSE / name, tmp_path / name)
    text = (WAREHOUSE / "warehouse.tsm").read_text(encoding="utf-8")
    plain = re.sub(r' external "[^"]*"', "", text)
    assert plain != text
    (tmp_path / "warehouse.tsm").write_text(plain, encoding="utf-8")
    unmarked = assert_check_agrees(load_product_line(tmp_path))
    assert (str(tmp_path / "warehouse.tsm"), 29, 20, "SPL045") in unmarked


def test_the_warehouse_findings_agree_with_every_product():
    findings = assert_check_agrees(load_product_line(WAREHOUSE))
    assert len(findings) == 2


@pytest.mark.parametrize("name", SHIPPED)
def test_each_shipped_line_agrees_with_every_product(name):
    assert_check_agrees(load_product_line(ROOT / "product_lines" / name))


def test_the_broken_line_agrees_with_every_product():
    line = load_product_line(ROOT / "tests" / "models" / "line_checks" / "broken")
    assert len(assert_check_agrees(line)) == 2


def test_random_statements_of_the_farm_line_agree_with_every_product(tmp_path, monkeypatch):
    """Statements connecting interfaces to topics, new topics, servers and bridges: the
    feeders they add or take away."""
    for name in ("farm.tsm", "farm.fm"):
        shutil.copy(FARM / name, tmp_path / name)
    monkeypatch.setattr(tsm, "parse_file", cache(tsm.parse_file))
    monkeypatch.setattr(fm_formats, "load_feature_model", cache(fm_formats.load_feature_model))
    checked = reported = 0
    for seed in range(400):
        (tmp_path / "farm.rm").write_text(resolution_model(random.Random(seed)))
        try:
            line = load_product_line(tmp_path)
        except ModelError:
            continue
        reported += len(assert_check_agrees(line))
        checked += 1
        if checked == 20:
            break
    assert checked == 20 and reported >= 20, (checked, reported)


@settings(max_examples=examples(25))
@given(line_specs())
def test_random_templates_agree_with_every_product(spec: LineSpec):
    assume(len(spec.features()) <= 5)
    with tempfile.TemporaryDirectory() as scratch:
        line = load_product_line(write_line(spec, Path(scratch) / "random"))
        assert_check_agrees(line)
