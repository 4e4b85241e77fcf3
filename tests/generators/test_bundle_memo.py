"""What bundles written together share (BundleMemo: Graphviz's quoting, YAML's plain
strings, the Rapyuta file sets found clean) is the caller's: bundles written with one
memo have the bytes they have alone, the memo is filled by them, and a bundle's
validation reuses its memo; without one, each bundle keeps its own."""

from __future__ import annotations

from pathlib import Path

from spl import pipeline
from spl.generators.bundle.inputs import BundleMemo
from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle
from spl.generators.rapyuta import rules as rapyuta_rules
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file

LINES = Path(__file__).resolve().parents[2] / "product_lines"
QUICK = BundleOptions(render_diagrams=False)


def products():
    line = load_product_line(LINES / "mapping3d")
    paths = sorted((LINES / "mapping3d" / "products").glob("*.yaml"))
    return [resolve(line, load_selection_file(path)).product for path in paths]


def test_bundles_sharing_a_memo_are_the_bundles_written_alone():
    memo = BundleMemo()
    for product in products():
        shared = build_bundle(product, QUICK, memo)
        assert shared.memo is memo
        assert shared.files == build_bundle(product, QUICK).files
    assert memo.quoted and memo.plain and memo.clean.keys  # every table was used


def test_a_bundle_without_a_memo_has_its_own_and_its_validation_reuses_it(monkeypatch):
    line = pipeline.load_line(LINES / "mapping3d")
    paper = load_selection_file(LINES / "mapping3d" / "products" / "youbot_stereo_room.yaml")
    derivation = pipeline.derive(line, paper, QUICK)
    other = pipeline.derive(line, paper, QUICK)
    assert derivation.bundle.memo is not other.bundle.memo
    assert len(derivation.bundle.memo.clean.keys) == 1  # its Rapyuta files, found clean
    checked = []
    monkeypatch.setattr(rapyuta_rules, "schema_problems", lambda c, n: checked.append(n) or [])
    assert pipeline.validate(derivation) == []
    assert checked == []  # the files read back are the set the generator found clean
    derivation.bundle.memo.clean.keys.clear()
    assert pipeline.validate(derivation) == []
    assert checked  # forgotten: checked again


def test_a_validation_run_shares_one_memo_among_its_products():
    from spl.validation.line import CaseChecks, ProductCase, run_case

    line = pipeline.load_line(LINES / "mapping3d")
    memo = BundleMemo()
    checks = CaseChecks(memo=memo)
    for path in sorted((LINES / "mapping3d" / "products").glob("*.yaml")):
        result = run_case(line, "mapping3d", ProductCase(0, path.stem, path), checks)
        assert result.outcome == "passed", result
    assert memo.clean.keys and memo.quoted and memo.plain
