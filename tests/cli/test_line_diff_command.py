"""``spl diff`` of two line folders and of a folder against a git revision (``--rev``),
``spl validate --since``, the folder being no change, and bad input (docs/evolution.md,
"Comparing two versions of a line")."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

from click.testing import CliRunner
from lxml import etree

from spl.cli import main

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"
WAREHOUSE = ROOT / "tests" / "models" / "line_checks" / "warehouse"
LOCATED_ERROR = re.compile(r"^\S.*:\d+:\d+: error: ", re.M)
SCHEMA = etree.XMLSchema(etree.parse(str(ROOT / "tests" / "junit" / "junit.xsd")))


def spl(*args: str | Path):
    result = CliRunner().invoke(main, [str(a) for a in args])
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    assert "Traceback" not in result.output
    return result


def products(*args: str | Path) -> dict:
    result = spl("diff", *args, "--json")
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)["products"]


def git(repo: Path, *args: str) -> None:
    env = {
        **os.environ,
        "GIT_AUTHOR_NAME": "t",
        "GIT_AUTHOR_EMAIL": "t@example.org",
        "GIT_COMMITTER_NAME": "t",
        "GIT_COMMITTER_EMAIL": "t@example.org",
        "GIT_CONFIG_GLOBAL": os.devnull,
    }
    subprocess.run(["git", "-C", str(repo), *args], check=True, capture_output=True, env=env)


def edit_camera(line: Path, device: str, was: str = "/dev/video1") -> None:
    """The right camera's device, a parameter of the stereo products' robot."""
    tsm = line / "mapping.tsm"
    text = tsm.read_text(encoding="utf-8")
    assert text.count(f'"{was}"') == 1
    tsm.write_text(text.replace(f'"{was}"', f'"{device}"'), encoding="utf-8")


def test_a_folder_against_its_last_commit_is_the_folders_compared(tmp_path: Path) -> None:
    """Two commits in a repository the test makes: ``--rev HEAD~1`` reports what ``spl
    diff`` of a copy of the first commit's folder and the folder reports, the work
    tree's uncommitted edit included; ``spl validate --since`` runs exactly the changed
    products."""
    repo = tmp_path / "repo"
    line = repo / "lines" / "mapping3d"
    shutil.copytree(MAPPING, line)
    first = shutil.copytree(MAPPING, tmp_path / "first" / "mapping3d")
    git(repo, "init", "-q")
    git(repo, "add", ".")
    git(repo, "commit", "-q", "-m", "first")
    edit_camera(line, "/dev/video7")
    git(repo, "commit", "-q", "-am", "second")
    at_revision = products("--rev", "HEAD~1", line, "--all")
    assert at_revision == products(first, line, "--all")
    changed = {p["product"] for p in at_revision["changed"]}
    assert changed and at_revision["unchanged"] > 0  # the stereo products only
    assert all("Stereo" in p["features"] for p in at_revision["changed"])
    reason = at_revision["changed"][0]["files"][0]["reason"]
    assert f"{line}/mapping.tsm:31:" in reason  # the parameter, where the new version writes it

    assert products("--rev", "HEAD", line)["changed"] == []
    # not committed: the work tree is the new version
    edit_camera(line, "/dev/video9", was="/dev/video7")
    assert {p["product"] for p in products("--rev", "HEAD", line, "--all")["changed"]} == changed

    junit = tmp_path / "report.xml"
    result = spl("validate", line, "--all", "--since", "HEAD~1", "--junit", junit)
    assert result.exit_code == 0, result.output
    report = etree.parse(str(junit))
    assert SCHEMA.validate(report), SCHEMA.error_log
    cases = list(report.getroot().iter("testcase"))
    assert report.getroot()[0].get("skipped") == str(len(cases) - len(changed))
    ran = {c.get("name") for c in cases if c.find("skipped") is None}
    assert ran == changed
    skips = {c.find("skipped").get("message") for c in cases if c.find("skipped") is not None}
    assert skips == {"bundle unchanged since HEAD~1"}
    assert result.stdout.endswith(
        f"{len(changed)} passed, 0 failed, {len(cases) - len(changed)} skipped\n"
    )


def test_revision_problems_are_one_line_errors(tmp_path: Path) -> None:
    outside = shutil.copytree(MAPPING, tmp_path / "plain" / "mapping3d")
    result = spl("diff", "--rev", "HEAD", outside)
    assert result.exit_code == 1
    assert result.stderr == f"error: {outside} is not in a git work tree\n"
    repo = tmp_path / "repo"
    line = shutil.copytree(MAPPING, repo / "mapping3d")
    git(repo, "init", "-q")
    git(repo, "add", ".")
    git(repo, "commit", "-q", "-m", "first")
    result = spl("diff", "--rev", "no-such-branch", line)
    assert result.exit_code == 1
    assert result.stderr.startswith("error: unknown git revision 'no-such-branch'")
    assert result.stderr.count("\n") == 1
    added = shutil.copytree(MAPPING, repo / "later")
    result = spl("diff", "--rev", "HEAD", added)
    assert result.exit_code == 1
    assert result.stderr == f"error: {added} is not in git revision 'HEAD': nothing to compare\n"
    # validate --since checks every product of a line the revision does not have
    result = spl("validate", added, "--since", "HEAD")
    assert result.exit_code == 0
    assert "every product is checked" in result.stderr
    assert "skipped" not in result.stdout


def test_a_broken_model_at_the_revision_is_located_as_git_names_it(tmp_path: Path) -> None:
    repo = tmp_path / "repo"
    line = shutil.copytree(MAPPING, repo / "mapping3d")
    (line / "mapping.tsm").write_text("system {\n", encoding="utf-8")
    git(repo, "init", "-q")
    git(repo, "add", ".")
    git(repo, "commit", "-q", "-m", "broken")
    shutil.copy(MAPPING / "mapping.tsm", line / "mapping.tsm")
    result = spl("diff", "--rev", "HEAD", line)
    assert result.exit_code == 1
    assert LOCATED_ERROR.search(result.stderr), result.stderr
    assert result.stderr.startswith(f"HEAD:{line}/mapping.tsm:1:"), result.stderr


def test_bad_folders_are_located_errors(tmp_path: Path) -> None:
    missing = tmp_path / "missing"
    result = spl("diff", MAPPING, missing)
    assert result.exit_code == 1
    assert result.stderr.startswith(f"error: {missing}: no such folder")
    empty = tmp_path / "empty"
    empty.mkdir()
    result = spl("diff", empty, MAPPING)
    assert result.exit_code == 1
    assert LOCATED_ERROR.search(result.stderr), result.stderr
    assert "a product line holds one .rm" in result.stderr
    broken = shutil.copytree(MAPPING, tmp_path / "broken")
    (broken / "mapping.rm").write_text('resolution model M\ntsm "mapping.tsm"\nfm "nothing.fm"\n')
    for old, new in ((broken, MAPPING), (MAPPING, broken)):
        result = spl("diff", old, new)
        assert result.exit_code == 1
        assert result.stderr.startswith(f"{broken}/mapping.rm:3:"), result.stderr
    result = spl("diff", MAPPING / "mapping.fm", MAPPING)
    assert result.exit_code == 1  # a model file is no line folder
    assert "not a folder" in result.stderr
    assert spl("diff", MAPPING, MAPPING, "--all", "--sample", "t=2").exit_code == 2
    assert spl("diff", "--rev", "HEAD", MAPPING, MAPPING).exit_code == 2


def test_the_folder_is_no_change_but_a_warning_that_moved_is(tmp_path: Path) -> None:
    """The warehouse's camera product warns at a .tsm line (SPL045), and its manifest
    names the file: read from another folder it is the same bundle; with a line added
    above the warning, the manifest says another line and the product changed."""
    old = shutil.copytree(WAREHOUSE, tmp_path / "a" / "warehouse")
    new = shutil.copytree(WAREHOUSE, tmp_path / "b" / "elsewhere")
    assert products(old, new) == {"added": [], "removed": [], "unchanged": 2, "changed": []}
    tsm = new / "warehouse.tsm"
    tsm.write_text("// a line above\n" + tsm.read_text(encoding="utf-8"), encoding="utf-8")
    found = products(old, new)
    assert [(p["product"], [f["path"] for f in p["files"]]) for p in found["changed"]] == [
        ("camera_detect", ["manifest.json"])
    ]


def test_the_report_for_people_groups_files_by_reason(tmp_path: Path) -> None:
    new = shutil.copytree(MAPPING, tmp_path / "mapping3d")
    edit_camera(new, "/dev/video7")
    result = spl("diff", MAPPING, new)
    assert result.exit_code == 0
    lines = result.stdout.splitlines()
    assert lines[0] == f"{MAPPING} -> {new}: refactoring (the same products)"
    assert "products: 2 changed, 3 unchanged, 0 added, 0 removed" in lines
    start = lines.index("  changed youbot_stereo_room (YouBot,Stereo,AdditionalPC,Room): 5 files")
    assert lines[start + 1] == (
        "    RGBCameraR.video_device: parameter = /dev/video7; nothing in this product decided "
        f"about it: as the template writes it ({new}/mapping.tsm:31:15)"
    )
    assert lines[start + 2] == (
        "      manifest.json, resolved.tsm, resolved.xmi, ros1/Robot.launch, ros2/Robot.launch.xml"
    )


def test_json_and_a_sample(tmp_path: Path) -> None:
    """``--json`` carries the feature model's comparison as ``spl diff`` of the two .fm
    files prints it; a t-wise sample's changed products are among ``--all``'s."""
    new = shutil.copytree(MAPPING, tmp_path / "mapping3d")
    edit_camera(new, "/dev/video7")
    result = spl("diff", MAPPING, new, "--json", "--sample", "t=1")
    assert result.exit_code == 0, result.stderr
    report = json.loads(result.stdout)
    assert set(report) == {"feature_model", "old", "new", "products"}
    assert (report["old"], report["new"]) == (str(MAPPING), str(new))
    models = spl("diff", MAPPING / "mapping.fm", new / "mapping.fm", "--json")
    assert report["feature_model"] == json.loads(models.stdout)
    assert set(report["products"]) == {"added", "removed", "unchanged", "changed"}
    sampled = {p["product"] for p in report["products"]["changed"]}
    every = {p["product"] for p in products(MAPPING, new, "--all")["changed"]}
    listed = {p["product"] for p in products(MAPPING, new)["changed"]}
    assert listed < sampled <= every
    for product in report["products"]["changed"]:
        assert set(product) == {"product", "features", "files"}
        assert all(set(f) == {"path", "reason"} for f in product["files"])


def test_since_reads_each_line_at_the_revision_of_its_own(tmp_path: Path) -> None:
    """Two lines with one folder name: each is compared with its own old version (its
    copy read out of git is its own, though the folder names are the same)."""
    repo = tmp_path / "repo"
    first = shutil.copytree(MAPPING, repo / "a" / "mapping3d")
    second = shutil.copytree(MAPPING, repo / "b" / "mapping3d")
    (second / "products" / "youbot_stereo_room.yaml").unlink()
    git(repo, "init", "-q")
    git(repo, "add", ".")
    git(repo, "commit", "-q", "-m", "two lines")
    junit = tmp_path / "report.xml"
    result = spl("validate", first, second, "--since", "HEAD", "--junit", junit)
    assert result.exit_code == 0, result.output
    suites = etree.parse(str(junit)).getroot()
    # one suite (the lines have one name): every product of both skipped
    assert [(s.get("tests"), s.get("skipped")) for s in suites] == [("9", "9")]
