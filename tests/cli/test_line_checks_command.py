"""``spl check DIR``: per-file summaries, the line checks on stderr, a summary line,
``--json``, exit status 1 on errors only; ``spl check FILE`` as before."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from spl.cli import main

ROOT = Path(__file__).resolve().parents[2]
MODELS = Path(__file__).parents[1] / "models" / "line_checks"
BROKEN = MODELS / "broken"


def run(*args: str):
    return CliRunner().invoke(main, list(args))


@pytest.mark.parametrize(
    ("name", "summary"),
    [
        ("mapping3d", "mapping3d: 9 resolution elements, 12 products, 0 errors, 0 warnings"),
        (
            "data_acquisition",
            # the info: PositionReader's GpsDeg, which no node reads (SPL052)
            "data_acquisition: 3 resolution elements, 12 products, 0 errors, 0 warnings, 1 info",
        ),
        ("orchard", "orchard: 9 resolution elements, 24 products, 0 errors, 0 warnings"),
    ],
)
def test_shipped_lines_pass(name, summary):
    result = run("check", str(ROOT / "product_lines" / name))
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert len(lines) == 4 and all(": ok: " in line for line in lines[:3])
    assert lines[-1] == summary
    assert all("info: " in line for line in result.stderr.splitlines())


def test_broken_line_prints_located_findings_and_fails():
    result = run("check", str(BROKEN))
    assert result.exit_code == 1
    assert result.stdout.splitlines()[-1] == (
        "broken: 16 resolution elements, 6144 products, 8 errors, 6 warnings, 1 info"
    )
    errors = result.stderr.splitlines()
    assert len(errors) == 15
    assert errors[1] == (
        f"{BROKEN}/broken.rm:6:1: error: resolution element 'when Gripper selected' can never "
        "be active: feature Gripper is dead (in no product), because Gripper requires Arm "
        f"({BROKEN}/broken.fm:29:5); Arm excludes Gripper ({BROKEN}/broken.fm:30:5) [SPL010]"
    )
    assert errors[5].startswith(f"{BROKEN}/broken.rm:30:5: error: conflict: 'when Local selected'")
    assert errors[5].endswith(
        "both are active in the product Base, Local, Remote, Robot, Sensing, Wheeled [SPL012]"
    )
    assert errors[9].endswith(
        "warning: Driver.cmd subscribes Robot.Cmd, which no node of the product publishes, in "
        "the product Base, Robot, Sensing, Wheeled [SPL045]"
    )
    assert errors[11] == (
        f"{BROKEN}/broken.tsm:24:19: warning: optional node Robot.Spare is in no product: "
        "no resolution element requires or transforms it [SPL011]"
    )


def test_json_lists_files_diagnostics_and_counts():
    result = run("check", "--json", str(BROKEN))
    assert result.exit_code == 1
    report = json.loads(result.stdout)
    assert [f["path"].rsplit("/", 1)[1] for f in report["files"]] == [
        "broken.fm",
        "broken.rm",
        "broken.tsm",
    ]
    assert report["files"][0] == {
        "path": f"{BROKEN}/broken.fm",
        "ok": True,
        "summary": "18 features, 3 constraints",
    }
    assert (report["errors"], report["warnings"], report["infos"]) == (8, 6, 1)
    assert report["line"] == {
        "name": "broken",
        "resolution_elements": 16,
        "products": 6144,
        "products_note": "",
        "listed_products": 3,
    }
    assert report["diagnostics"][0] == {
        "file": f"{BROKEN}/broken.fm",
        "line": 25,
        "col": 14,
        "severity": "info",
        "code": "SPL014",
        "message": "feature Beeper has no effect: no resolution element, attribute, "
        "sharing mode or constraint mentions it",
    }
    assert report["summary"].startswith("broken: 16 resolution elements")
    assert run("check", "--json", str(BROKEN)).stdout == result.stdout  # deterministic


def test_warnings_and_infos_alone_exit_zero(tmp_path):
    line = tmp_path / "line"
    shutil.copytree(ROOT / "product_lines" / "mapping3d", line)
    tsm = line / "mapping.tsm"
    text = tsm.read_text(encoding="utf-8")
    tsm.write_text(
        text.replace(
            "    optional node DepthCamera {",
            "    optional node Unused {\n        implementation spare/unused\n    }\n"
            "    optional node DepthCamera {",
            1,
        ),
        encoding="utf-8",
    )
    result = run("check", str(line))
    assert result.exit_code == 0, result.output
    assert "warning: optional node Robot.Unused is in no product" in result.stderr
    assert result.stdout.splitlines()[-1].endswith("0 errors, 1 warning")
    assert json.loads(run("check", "--json", str(line)).stdout)["warnings"] == 1


def test_migration_targets_missing_or_already_there_are_reported():
    result = run("check", str(MODELS / "bad_migration"))
    assert result.exit_code == 1
    rm = MODELS / "bad_migration" / "bad.rm"
    assert result.stderr.splitlines() == [
        f"{rm}:6:5: error: unknown container Fog [SPL013]",
        f"{rm}:9:5: error: node Planner is declared in container Cloud: a migration moves a "
        "node to another container [SPL013]",
    ]
    assert result.stdout.splitlines()[-1] == (
        "bad_migration: 2 errors, 0 warnings (not checked as a product line: its models do "
        "not parse)"
    )


def test_single_file_output_is_unchanged():
    result = run("check", str(BROKEN / "broken.rm"))
    assert result.exit_code == 0
    assert result.stdout == f"{BROKEN}/broken.rm: ok: 16 resolution elements, 17 transformations\n"
    assert result.stderr == ""


def test_single_file_json(tmp_path):
    bad = tmp_path / "bad.rm"
    bad.write_text((MODELS / "bad_migration" / "bad.rm").read_text(encoding="utf-8"))
    shutil.copy(MODELS / "bad_migration" / "bad.tsm", tmp_path)
    shutil.copy(MODELS / "bad_migration" / "bad.fm", tmp_path)
    result = run("check", "--json", str(bad))
    assert result.exit_code == 1
    report = json.loads(result.stdout)
    assert report["line"] is None and report["summary"] is None
    assert [(d["line"], d["message"]) for d in report["diagnostics"]] == [
        (6, "unknown container Fog"),
        (
            9,
            "node Planner is declared in container Cloud: a migration moves a node to another "
            "container",
        ),
    ]


def test_folder_without_resolution_model_is_checked_file_by_file(tmp_path):
    shutil.copy(MODELS / "bad_migration" / "bad.tsm", tmp_path)
    shutil.copy(MODELS / "bad_migration" / "bad.fm", tmp_path)
    result = run("check", str(tmp_path))
    assert result.exit_code == 0
    assert result.stdout.splitlines()[-1] == (
        f"{tmp_path.name}: 0 errors, 0 warnings (not checked as a product line: no .rm files; "
        "a product line holds one)"
    )


def test_counts_of_one_are_singular():
    line = Path(__file__).parents[1] / "models" / "validate" / "rapyuta_clash"
    result = run("check", str(line))
    assert result.exit_code == 0, result.output
    assert ": ok: 2 containers, 3 nodes, 2 topics, 3 interfaces, 1 bridge\n" in result.stdout
    analysed = run("analyze", str(ROOT / "product_lines" / "mapping3d" / "mapping.fm"))
    assert analysed.stdout.splitlines()[0].endswith(": 12 features, 1 constraint")


def test_a_folder_with_two_resolution_models_fails_check_as_it_fails_resolve(tmp_path):
    # was: spl check "0 errors", exit 0, on a folder spl resolve and spl validate refuse
    line = tmp_path / "two"
    shutil.copytree(ROOT / "product_lines" / "mapping3d", line)
    shutil.copy(line / "mapping.rm", line / "other.rm")
    refusal = (
        f"{line / 'other.rm'}:1:1: error: a product line holds one .rm, and mapping.rm is this "
        "folder's first: move or remove other.rm"
    )
    checked = run("check", str(line))
    assert (checked.exit_code, checked.stderr) == (1, refusal + "\n")
    assert checked.stdout.splitlines()[-1] == (
        "two: 1 error, 0 warnings (not checked as a product line: 2 .rm files; a product line "
        "holds one)"
    )
    resolved = run(
        "resolve", str(line), "--features", "YouBot,Stereo,Room", "-o", str(tmp_path / "o")
    )
    assert (resolved.exit_code, resolved.stderr) == (1, refusal + "\n")


def test_a_robot_container_without_what_the_client_needs_fails_check(tmp_path):
    # was: spl check "0 errors", then 33 of 82 products failed validate for want of it
    line = tmp_path / "noendpoint"
    shutil.copytree(
        ROOT / "product_lines" / "mapping3d", line, ignore=shutil.ignore_patterns("fleets")
    )
    tsm = line / "mapping.tsm"
    endpoint = (
        '    endpoint robot_id "robot_1" url "wss://cloud.example.org:9000/" user "mapper"\n'
        '             password env "RCE_PASSWORD"\n'
    )
    text = tsm.read_text()
    assert endpoint in text
    tsm.write_text(text.replace(endpoint, ""))
    checked = run("check", str(line))
    assert checked.exit_code == 1
    assert checked.stderr.splitlines() == [
        f"{tsm}:7:17: warning: robot container Robot: its endpoint has no robot_id and no url: "
        "every product keeping it must set them in its deployment [SPL018]",
        f"{tsm}:7:17: error: robot container Robot: its endpoint has no user and no password "
        "env: every product keeping it fails to resolve (the rce-ros client needs them, and a "
        "deployment cannot set them) [SPL018]",
    ]
    # robot_id and url alone are what a product's deployment can give
    tsm.write_text(text.replace('robot_id "robot_1" url "wss://cloud.example.org:9000/" ', ""))
    checked = run("check", str(line))
    assert checked.exit_code == 0
    assert "its endpoint has no robot_id and no url" in checked.stderr


def _mapping_copy(tmp_path: Path) -> Path:
    line = tmp_path / "tags"
    shutil.copytree(
        ROOT / "product_lines" / "mapping3d", line, ignore=shutil.ignore_patterns("fleets")
    )
    return line


def test_a_robot_id_naming_a_cloud_partition_is_a_warning_where_resolve_fails(tmp_path):
    # was: spl check "0 errors, 0 warnings", then every product failed validate
    line = _mapping_copy(tmp_path)
    tsm = line / "mapping.tsm"
    # the protected partition of MappingCloud (group mappers) is MappingCloud_mappers: its
    # mode is the feature model's default for SharedMap's nodes, not the .tsm's
    tsm.write_text(tsm.read_text().replace('robot_id "robot_1"', 'robot_id "MappingCloud_mappers"'))
    clash = (
        "Rapyuta tag 'MappingCloud_mappers' would name both robot container Robot and the "
        "protected partition of MappingCloud: rename a container, group or robot_id"
    )
    checked = run("check", str(line))
    assert checked.exit_code == 0
    assert checked.stderr.splitlines() == [
        f"{tsm}:59:17: warning: {clash}; a product that has both fails to resolve [SPL019]"
    ]
    validated = run("validate", str(line), "--all")
    assert validated.exit_code == 1
    assert f"{tsm}:59:17: error: {clash}" in validated.output
    # a tag only a public partition would take: no node of MappingCloud is public unless a
    # selection says so, and only a listed product does
    tsm.write_text(
        tsm.read_text().replace('robot_id "MappingCloud_mappers"', 'robot_id "MappingCloud_public"')
    )
    listed = line / "products" / "youbot_depth_room_pc.yaml"
    assert "SharedMap: public" in listed.read_text()
    checked = run("check", str(line))
    assert checked.stderr.count("[SPL019]") == 1
    assert "'MappingCloud_public' would name both robot container Robot and the public" in (
        checked.stderr
    )
    shutil.rmtree(line / "products")
    assert run("check", str(line)).stderr == ""
    assert run("validate", str(line), "--all").exit_code == 0


def test_a_node_migrated_to_a_cloud_container_makes_its_partition_there(tmp_path):
    line = _mapping_copy(tmp_path)
    shutil.rmtree(line / "products")
    tsm, rm = line / "mapping.tsm", line / "mapping.rm"
    # a public robot node that Corridor products run in MappingCloud's public partition
    text = tsm.read_text().replace(
        "node RobotController {", "node RobotController sharing public {"
    )
    tsm.write_text(text.replace('robot_id "robot_1"', 'robot_id "MappingCloud_public"'))
    assert run("check", str(line)).stderr == ""  # on the robot it is no partition
    rm.write_text(
        rm.read_text() + "when Corridor selected { migrate RobotController to MappingCloud }\n"
    )
    checked = run("check", str(line))
    assert checked.stderr.count("[SPL019]") == 1
    assert "the public partition of MappingCloud" in checked.stderr
    validated = run("validate", str(line), "--all")
    assert validated.output.count("FAIL") == 6  # the Corridor products
