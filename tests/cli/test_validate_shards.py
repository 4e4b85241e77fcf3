"""``spl validate --shard K/N`` and ``spl merge-junit``: the shards of a run are a
partition of its plan, and their reports merge into the unsharded run's report, byte for
byte; a merge refuses anything but the complete shards of one run (docs/ci.md)."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import given, strategies as st

from spl.cli import main
from spl.validation.line import ProductCase, Shard

ROOT = Path(__file__).resolve().parents[2]
MODELS = Path(__file__).parents[1] / "models" / "validate"
# two shipped lines with all their products, a line with a failing product and one that
# does not load: every kind of case a shard can hold
LINES = [
    ROOT / "product_lines" / "data_acquisition",
    ROOT / "product_lines" / "mapping3d",
    MODELS / "conflicting",
    MODELS / "unloadable",
]


def spl(*args: object):
    return CliRunner().invoke(main, [str(a) for a in args])


@given(st.integers(0, 60), st.integers(1, 12))
def test_the_shards_partition_the_plan_in_order(length: int, count: int) -> None:
    cases = [ProductCase(0, f"p{i}") for i in range(length)]
    parts = [Shard(k, count).of(cases) for k in range(1, count + 1)]
    assert [case for part in parts for case in part] == cases
    assert max(map(len, parts)) - min(map(len, parts)) <= 1


@pytest.mark.parametrize("text", ["0/3", "4/3", "x", "1/", "/2", "1/0", "-1/2", "١/٢", " 1/2"])
def test_a_shard_is_k_of_n(text: str) -> None:
    with pytest.raises(ValueError):
        Shard.parse(text)
    result = spl("validate", LINES[0], "--shard", text)
    assert result.exit_code == 2
    assert "Invalid value for --shard" in result.output


@pytest.fixture(scope="module")
def whole(tmp_path_factory) -> bytes:
    report = tmp_path_factory.mktemp("whole") / "validate.xml"
    result = spl("validate", *LINES, "--all", "--junit", report)
    assert result.exit_code == 1  # the failing product and the line that does not load
    return report.read_bytes()


@pytest.fixture(scope="module")
def shards(tmp_path_factory) -> list[Path]:
    folder = tmp_path_factory.mktemp("shards")
    reports = []
    for k in (1, 2, 3):
        report = folder / f"shard-{k}.xml"
        result = spl("validate", *LINES, "--all", "--shard", f"{k}/3", "--junit", report)
        assert result.exit_code in (0, 1), result.output
        reports.append(report)
    return reports


def test_the_merged_shards_are_the_whole_report(whole, shards, tmp_path) -> None:
    merged = tmp_path / "merged.xml"
    result = spl("merge-junit", shards[2], shards[0], shards[1], "-o", merged)
    assert result.exit_code == 1  # a product failed in the run
    assert merged.read_bytes() == whole
    assert result.output.endswith("3 shards, 38 passed, 4 failed\n")


def test_each_case_is_in_one_shard(whole, shards) -> None:
    from lxml import etree

    def names(data: bytes) -> list[tuple[str, str]]:
        root = etree.fromstring(data)
        return [(c.get("classname"), c.get("name")) for c in root.iter("testcase")]

    parts = [names(path.read_bytes()) for path in shards]
    assert [case for part in parts for case in part] == names(whole)
    assert [len(part) for part in parts] == [14, 14, 14]
    assert parts[0][0] == ("unloadable", "(product line)")  # first in the plan


def test_the_merge_refuses_a_partial_or_foreign_run(whole, shards, tmp_path) -> None:
    out = tmp_path / "merged.xml"
    unsharded = tmp_path / "whole.xml"
    unsharded.write_bytes(whole)
    other = tmp_path / "other-1.xml"  # shard 1/3 of another run: other lines
    assert spl("validate", LINES[0], "--shard", "1/3", "--junit", other).exit_code == 0
    broken = tmp_path / "broken.xml"
    broken.write_text('<?xml version="1.0"?>\n<testsuites name="spl validate"\n')
    refusals = {
        (shards[0], shards[2]): "error: shard 2 of 3 is missing",
        (
            shards[0],
            shards[0],
            shards[1],
            shards[2],
        ): f"error: {shards[0]}: shard 1/3 is given twice",
        (other, shards[1], shards[2]): "error: the reports are of different runs",
        (unsharded,): f"error: {unsharded}: not the report of a shard",
        (broken,): f"error: {broken}:3:1: not XML: ",
    }
    for reports, message in refusals.items():
        result = spl("merge-junit", *reports, "-o", out)
        assert result.exit_code == 1
        assert result.output.startswith(message), result.output
        assert "Traceback" not in result.output
        assert not out.exists()  # nothing half-written
