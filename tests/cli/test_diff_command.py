"""``spl diff OLD NEW``: the JSON contract, the readable report, exit statuses, and two
versions read from different formats."""

from __future__ import annotations

import json
import re
from pathlib import Path

from click.testing import CliRunner
from hypothesis import given, settings, strategies as st

from spl.cli import main

from support.cli_outcome import assert_clean
from support.hypothesis_budget import examples
from support.model_mutations import mutate, mutations
from support.real_models import REAL_MODELS

BUSYBOX = REAL_MODELS / "evolution" / "busybox"
JUNE, JULY = BUSYBOX / "2007-06-01_14-40-03.uvl", BUSYBOX / "2007-07-01_14-53-06.uvl"
MAY = BUSYBOX / "2007-05-20_17-12-43.uvl"
BERKELEY = REAL_MODELS / "berkeleydb.uvl"
KEYS = {
    "classification",
    "added",
    "removed",
    "moved",
    "constraints",
    "witnesses",
    "counts",
    "counts_note",
}


def run(*args: str | Path):
    return CliRunner().invoke(main, [str(arg) for arg in args])


def diff_json(*args: str | Path) -> dict:
    result = run("diff", "--json", *args)
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


def analysed_count(path: Path) -> int:
    result = run("analyze", "--json", "--count", path)
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)["products"]


def without_line(source: Path, line: str, target: Path) -> Path:
    text = source.read_text(encoding="utf-8")
    assert f"\t{line}\n" in text
    target.write_text(text.replace(f"\t{line}\n", ""), encoding="utf-8")
    return target


def test_json_of_an_arbitrary_edit() -> None:
    report = diff_json(JUNE, JULY, "--count")
    assert set(report) == KEYS
    assert report["classification"] == "arbitrary"
    assert report["removed"] == ["CONFIG_WATCH"] and len(report["added"]) == 16
    assert report["moved"] == []
    assert report["constraints"]["removed"] == ["CONFIG_DATE or not CONFIG_WATCH"]
    assert len(report["constraints"]["added"]) == 18
    witnesses, counts = report["witnesses"], report["counts"]
    assert set(witnesses) == set(counts) == {"old_not_new", "new_not_old"}
    assert all(w == sorted(w) and w for w in witnesses.values())
    # a product of a version selects none of the features that version lacks
    assert not set(witnesses["old_not_new"]) & set(report["added"])
    assert "CONFIG_WATCH" not in witnesses["new_not_old"]
    assert all(isinstance(c, int) and c > 0 for c in counts.values())
    assert report["counts_note"] == ""


def test_a_refactoring_exits_0_with_empty_lists() -> None:
    report = diff_json(MAY, JUNE)
    assert report["classification"] == "refactoring"
    assert report["witnesses"] == {"old_not_new": None, "new_not_old": None}
    assert report["counts"] == {"old_not_new": 0, "new_not_old": 0}
    assert report["added"] == report["removed"] == report["moved"] == []


def test_a_removed_constraint_generalizes_by_the_difference_of_the_counts(
    tmp_path: Path,
) -> None:
    edited = without_line(
        BERKELEY, "featureStatisticsEnvFSync => featureFSync", tmp_path / "berkeleydb.uvl"
    )
    report = diff_json(BERKELEY, edited, "--count")
    assert report["classification"] == "generalization"
    assert report["constraints"] == {
        "added": [],
        "removed": ["featureStatisticsEnvFSync => featureFSync"],
    }
    # OLD's products are all NEW's: what was added is the difference of the totals
    added = analysed_count(edited) - analysed_count(BERKELEY)
    assert report["counts"] == {"old_not_new": 0, "new_not_old": added} and added > 0
    witness = report["witnesses"]["new_not_old"]
    assert "featureStatisticsEnvFSync" in witness and "featureFSync" not in witness
    # and the other way round it is a specialization
    back = diff_json(edited, BERKELEY, "--count")
    assert back["classification"] == "specialization"
    assert back["counts"] == {"old_not_new": added, "new_not_old": 0}


def test_the_readable_report(tmp_path: Path) -> None:
    result = run("diff", JUNE, JULY, "--count")
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0] == f"{JUNE} -> {JULY}: arbitrary (products added and removed)"
    assert re.fullmatch(r"  products removed: \d+", lines[1])
    assert re.fullmatch(r"  products added:   \d+", lines[2])
    assert lines[3].startswith("  a removed product (11 features): ")
    assert lines[4].startswith("  an added product (11 features): ")
    assert lines[5].startswith("  features added (16): CONFIG_FEATURE_EDITING_MAX_LEN, ")
    assert lines[5].endswith(" ... and 6 more")
    assert lines[6:9] == [
        "  features removed (1): CONFIG_WATCH",
        "  features moved (0): -",
        lines[8],
    ]
    assert lines[8].startswith("  constraints added (18): ") and "; " in lines[8]
    assert lines[9] == "  constraints removed (1): CONFIG_DATE or not CONFIG_WATCH"


def test_counts_past_their_bound_are_null_with_a_note() -> None:
    report = diff_json(JUNE, JULY, "--count-seconds", "0")
    assert report["classification"] == "arbitrary"
    assert report["counts"] == {"old_not_new": None, "new_not_old": None}
    assert report["counts_note"] == "not counted within 0 s"
    text = run("diff", JUNE, JULY, "--count-seconds", "0").stdout.splitlines()
    assert text[1] == (
        "  products removed: unknown (not counted within 0 s; --count counts without a time bound)"
    )


def test_the_output_is_the_same_bytes_every_run() -> None:
    first = run("diff", "--json", "--count", JUNE, JULY).stdout
    assert first == run("diff", "--json", "--count", JUNE, JULY).stdout


def test_uvl_against_featureide_xml_of_the_same_model() -> None:
    for name in ("axTLS", "berkeleydb"):
        report = diff_json(REAL_MODELS / f"{name}.uvl", REAL_MODELS / f"{name}.xml")
        assert report["classification"] == "refactoring", name
        assert report["added"] == report["removed"] == report["moved"] == [], name
        assert report["constraints"] == {"added": [], "removed": []}, name


def test_a_converted_fm_against_its_uvl(tmp_path: Path) -> None:
    # three formats: the .fm written by spl convert from the XML, against the UVL
    converted = tmp_path / "axTLS.fm"
    assert run("convert", REAL_MODELS / "axTLS.xml", converted).exit_code == 0
    report = diff_json(REAL_MODELS / "axTLS.uvl", converted)
    assert report["classification"] == "refactoring"
    assert report["added"] == report["removed"] == []
    assert report["constraints"] == {"added": [], "removed": []}


def test_a_model_that_does_not_parse_is_a_located_error(tmp_path: Path) -> None:
    broken = tmp_path / "broken.uvl"
    broken.write_text("features\n\tRoot\n\t\toptional\n\t\t\tA {\n", encoding="utf-8")
    for args in ((broken, MAY), (MAY, broken)):
        result = run("diff", *args)
        assert result.exit_code == 1, result.output
        assert re.match(rf"{re.escape(str(broken))}:\d+:\d+: error: ", result.stderr)
        assert "Traceback" not in result.output and result.stdout == ""


def test_a_constraint_on_an_unknown_feature_is_a_located_error(tmp_path: Path) -> None:
    model = tmp_path / "unknown.fm"
    model.write_text(
        "feature model M\n\nroot R {\n    optional A\n}\n\nconstraints {\n    A requires B\n}\n",
        encoding="utf-8",
    )
    result = run("diff", model, model)
    assert result.exit_code == 1, result.output
    assert result.stderr.startswith(f"{model}:8:")


def test_usage_errors_exit_2(tmp_path: Path) -> None:
    text = tmp_path / "model.txt"
    text.write_text("features\n\tRoot\n", encoding="utf-8")
    assert run("diff", text, MAY).exit_code == 2
    assert run("diff", MAY, tmp_path / "missing.uvl").exit_code == 2
    assert run("diff", MAY, JUNE, "--count", "--count-seconds", "1").exit_code == 2


ROBOT = """features
\tRobot
\t\toptional
\t\t\t"Mobile base"
\t\t\t"Lidar 2D"
"""


def test_names_are_reported_as_the_files_write_them(tmp_path: Path) -> None:
    old = tmp_path / "old.uvl"
    old.write_text(ROBOT, encoding="utf-8")
    new = tmp_path / "new.uvl"
    new.write_text(
        ROBOT + '\t\t\t"Extra sensor"\n\nconstraints\n\t"Extra sensor" => "Lidar 2D"\n',
        encoding="utf-8",
    )
    report = diff_json(old, new, "--count")
    assert report["classification"] == "generalization"
    assert report["added"] == ["Extra sensor"]
    assert report["constraints"]["added"] == ['"Extra sensor" => "Lidar 2D"']
    added_product = report["witnesses"]["new_not_old"]
    assert {"Extra sensor", "Lidar 2D", "Robot"} <= set(added_product)
    assert report["counts"] == {"old_not_new": 0, "new_not_old": 2}
    # .fm cannot carry these names: the converted file keeps them as original_name,
    # and the comparison matches features by them
    converted = tmp_path / "new.fm"
    assert run("convert", new, converted).exit_code == 0
    assert "Extra_sensor" in converted.read_text(encoding="utf-8")
    same = diff_json(new, converted)
    assert same["classification"] == "refactoring"
    assert same["added"] == same["removed"] == [] and same["constraints"]["added"] == []


def test_a_void_version_has_no_products_to_add_or_keep(tmp_path: Path) -> None:
    void = Path(__file__).parents[1] / "models" / "analysis" / "void.fm"
    fixed = tmp_path / "fixed.fm"
    fixed.write_text(
        void.read_text(encoding="utf-8").replace("A excludes R", "B requires A"),
        encoding="utf-8",
    )
    # R and A in both products, B free: two products, both removed by the void version
    report = diff_json(fixed, void, "--count")
    assert report["classification"] == "specialization"
    assert report["counts"] == {"old_not_new": 2, "new_not_old": 0}
    assert report["constraints"] == {"added": ["A => not R"], "removed": ["B => A"]}
    assert diff_json(void, fixed, "--count")["classification"] == "generalization"
    assert diff_json(void, void)["classification"] == "refactoring"


def test_two_features_written_with_one_name_are_a_located_error(tmp_path: Path) -> None:
    model = tmp_path / "twice.fm"
    model.write_text(
        "feature model M\n\nroot R {\n"
        '    optional A { attribute original_name : string = "Lidar" }\n'
        '    optional B { attribute original_name : string = "Lidar" }\n}\n',
        encoding="utf-8",
    )
    result = run("diff", model, MAY)
    assert result.exit_code == 1, result.output
    assert result.stderr.startswith(f"{model}:5:")
    assert "features A and B are both named 'Lidar'" in result.stderr


FUZZED = [REAL_MODELS / "berkeleydb.uvl", REAL_MODELS / "berkeleydb.xml", MAY]


@st.composite
def mutated_versions(draw):
    source = draw(st.sampled_from(FUZZED))
    text = source.read_text(encoding="utf-8")
    return source, mutate(text, draw(mutations(text)))


@settings(max_examples=examples(30))
@given(mutated_versions(), st.booleans())
def test_a_mutated_version_is_compared_or_refused_with_a_located_error(
    tmp_path_factory, case, mutant_is_new: bool
) -> None:
    source, text = case
    mutant = tmp_path_factory.mktemp("mutant") / source.name
    mutant.write_text(text, encoding="utf-8", errors="surrogateescape")
    pair = (source, mutant) if mutant_is_new else (mutant, source)
    result = run("diff", "--json", "--count-seconds", "1", *pair)
    assert_clean(result, f"spl diff of {source.name} and its mutant:\n{text!r}")
    if result.exit_code == 0:
        assert set(json.loads(result.stdout)) == KEYS
