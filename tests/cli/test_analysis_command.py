"""``spl analyze``: the JSON contract and the readable report, on .fm and .uvl files."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from spl.cli import main

from support.real_models import REAL_MODELS

HERE = Path(__file__).parents[1] / "models" / "analysis"
BERKELEY = REAL_MODELS / "berkeleydb.uvl"


def run(*args: str):
    return CliRunner().invoke(main, ["analyze", *map(str, args)])


def test_json_on_the_mapping_feature_model() -> None:
    result = run(HERE / "mapping.fm", "--json")
    assert result.exit_code == 0, result.output
    report = json.loads(result.output)
    assert report["features"] == 13 and report["constraints"] == 3
    assert report["satisfiable"] is True
    # by hand: 2 environments x 2 (CollaborativeMapping) x 8 over (base, sensor, PC, Logging):
    # YouBot+Stereo needs the PC (2: Logging or not), YouBot+Depth and Roomba+Depth 3 each
    # (no PC and no Logging, or PC with or without Logging), Roomba+Stereo none
    assert report["products"] == 32 and report["products_note"] == ""
    assert report["core"] == ["Environment", "Mapping", "MobileBase", "PerceptionSensor"]
    assert report["dead"] == [] and report["false_optional"] == []
    assert isinstance(report["seconds"], float)


def test_void_model() -> None:
    report = json.loads(run(HERE / "void.fm", "--json").output)
    assert report["satisfiable"] is False and report["products"] == 0
    assert report["dead"] == ["A", "B", "R"] and report["core"] == []


def test_uvl_and_readable_report() -> None:
    result = run(BERKELEY)
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert lines[0].endswith("76 features, 20 constraints")
    assert "  products:       4080389785" in lines
    assert "  false-optional (2): featureDeleteDb, featureTruncateDb" in lines


def test_count_bound_gives_null_and_a_note() -> None:
    report = json.loads(run(BERKELEY, "--json", "--count-seconds", "0").output)
    assert report["products"] is None and "count skipped" in report["products_note"]


def test_featureide_xml_gives_the_same_analysis_as_uvl() -> None:
    uvl = json.loads(run(BERKELEY, "--json").output)
    xml = json.loads(run(BERKELEY.with_suffix(".xml"), "--json").output)
    for report in (uvl, xml):
        del report["seconds"], report["name"]
    assert xml == uvl


def test_unreadable_model_is_a_located_error(tmp_path: Path) -> None:
    bad = tmp_path / "bad.fm"
    bad.write_text("feature model X\nroot R {\n  mandatory\n}\n")
    result = run(bad)
    assert result.exit_code == 1
    assert str(bad) in result.output and "error" in result.output


def test_file_that_is_not_utf8_is_a_located_error(tmp_path: Path) -> None:
    for suffix in (".uvl", ".fm"):
        bad = tmp_path / f"latin1{suffix}"
        bad.write_bytes(b"features\n\tCaf\xe9\n")
        result = run(bad)
        assert result.exit_code == 1, result.output
        assert f"{bad}:2:5: error: file is not UTF-8 text" in result.output


def test_count_flag_and_default_bound() -> None:
    counted = json.loads(run(BERKELEY, "--json", "--count").output)
    assert counted["products"] == 4080389785 and counted["products_note"] == ""
    # the default bound is at least a second: BerkeleyDB counts within it
    default = json.loads(run(BERKELEY, "--json").output)
    assert default["products"] == 4080389785
    both = run(BERKELEY, "--count", "--count-seconds", "3")
    assert both.exit_code == 2 and "either --count or --count-seconds" in both.output


def test_skipped_count_is_said_plainly() -> None:
    result = run(BERKELEY, "--count-seconds", "0")
    assert result.exit_code == 0, result.output
    assert (
        "  products:       unknown (count skipped after 0 s; --count counts without a time bound)"
        in result.output.splitlines()
    )


def test_a_model_that_is_no_feature_model_is_a_usage_error() -> None:
    # was: exit 1 with "mapping.tsm:1:1: error: ... unsupported feature-model format",
    # where spl products says the same as a usage error, exit 2
    tsm = Path(__file__).resolve().parents[2] / "product_lines" / "mapping3d" / "mapping.tsm"
    result = run(tsm)
    assert result.exit_code == 2
    assert "expected a .fm, .uvl or .xml feature model" in result.output


def test_nan_seconds_are_refused() -> None:
    # was accepted, and the count ran without any bound
    result = run(BERKELEY, "--count-seconds", "nan")
    assert result.exit_code == 2
    assert "nan is not a number of seconds" in result.output
