"""SPL016 against the Resolution Engine, on random resolution models of the farm line
(tests/models/semantics): the witness product of every SPL016 finding fails to resolve,
at that statement or at one before it (SPL016 asks about each statement as if the ones
before it succeeded); and where a product first fails, for a reason SPL016 covers (a
topic missing where it is looked up, a client and server apart, a service bridge inside
one container, a migration onto a node name), SPL016 reported that statement. Seeds are
fixed and the number of lines bounded, so the test is deterministic and takes seconds."""

from __future__ import annotations

import itertools
import random
import shutil
from functools import cache

from spl.core.diagnostics import ModelError
from spl.dsl.interop import formats as fm_formats
from spl.dsl.tsm import language as tsm
from spl.resolver.line_checks import check_product_line
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.farm_statements import FEATURES, MODELS, resolution_model

LINES = 25  # random lines that parse, each checked and resolved in all 12 products
COVERED = ("unknown topic", "cannot migrate", "is served in container", "a bridge connects")


def products() -> list[list[str]]:
    """The farm line's 12 products (LocalPlanning requires Planning)."""
    found = []
    for choice in itertools.product([False, True], repeat=4):
        features = [f for f, on in zip(FEATURES[1:], choice, strict=True) if on]
        if "LocalPlanning" not in features or "Planning" in features:
            found.append(["Farm", *features])
    return found


def located(diagnostic) -> tuple[int, int]:
    return diagnostic.location.line, diagnostic.location.col


def in_rm(error: ModelError) -> list:
    """The errors of a resolution located in the .rm (statements, conflicts)."""
    found = [d for d in error.diagnostics if d.location and d.location.file.endswith(".rm")]
    assert found, [str(d) for d in error.diagnostics]
    return found


def test_spl016_agrees_with_resolving_every_product(tmp_path, monkeypatch):
    for name in ("farm.tsm", "farm.fm"):
        shutil.copy(MODELS / name, tmp_path / name)
    # the .tsm and .fm are the same for every line: parsed once (resolving copies them)
    monkeypatch.setattr(tsm, "parse_file", cache(tsm.parse_file))
    monkeypatch.setattr(fm_formats, "load_feature_model", cache(fm_formats.load_feature_model))
    checked = reported = failures = 0
    for seed in itertools.count():
        assert seed < 2000, "too few random lines parse"
        (tmp_path / "farm.rm").write_text(resolution_model(random.Random(seed)))
        try:
            line = load_product_line(tmp_path)
        except ModelError:
            continue  # refused statically: C1, tested elsewhere
        findings = [d for d in check_product_line(line, products=False) if d.code == "SPL016"]
        for finding in findings:  # the witness fails there, or at a statement before
            witness = finding.message.rsplit(", in the product ", 1)[1].replace(" ", "")
            try:
                resolve(line, selection_from_list(witness))
                raise AssertionError(f"seed {seed}: {finding} but {witness} resolves")
            except ModelError as error:
                assert min(located(d) for d in in_rm(error)) <= located(finding), seed
        flagged = {located(d) for d in findings}
        for features in products():  # where a product first fails, SPL016 said so
            try:
                resolve(line, selection_from_list(",".join(features)))
            except ModelError as error:
                first = min(in_rm(error), key=located)
                if any(kind in first.message for kind in COVERED):
                    failures += 1
                    assert located(first) in flagged, f"seed {seed}, {features}: {first}"
        reported += len(findings)
        checked += 1
        if checked == LINES:
            break
    assert reported >= 5 and failures >= 5, (reported, failures)  # SPL016 was exercised
