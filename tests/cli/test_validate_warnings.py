"""``spl validate`` and the warnings of a product (docs/ci.md, "A product's warnings"): an
input nothing feeds (SPL045, as ``spl check`` finds it for the line and ``spl resolve``
for the product) and an output the product cannot have (``zenoh/`` Zenoh cannot carry)
are printed under the product's line, counted, carried in its JUnit test case, and a
failure only with ``--strict``; an input the model says is fed from outside is neither.
``spl resolve``, ``spl fleet resolve`` and the manifests say the same."""

from __future__ import annotations

import json
import os
import pty
import shutil
import subprocess
from pathlib import Path

from click.testing import CliRunner
from lxml import etree

from spl.cli import main

from support.smoke_runs import run_spl, spl_command

ROOT = Path(__file__).resolve().parents[2]
WAREHOUSE = ROOT / "tests" / "models" / "line_checks" / "warehouse"
SCHEMA = etree.XMLSchema(etree.parse(str(ROOT / "tests" / "junit" / "junit.xsd")))
# The cloud renames the camera's /camera/image to /shelf/image: a bridge renaming a topic
# other than by a namespace in front of it, which no choice of Zenoh namespaces gives
# (docs/deployment.md, "What Zenoh cannot carry"), so every camera product goes without
# zenoh/ whatever the Zenoh generator learns; the lidar products never use the topic.
SKIP = (
    "warning: zenoh/ not written: Zenoh cannot carry this product: the topic /camera/image "
    "of amr_1 arrives in Cloud_amr_1 as /shelf/image (Amr.Camera.image -> "
    "Cloud.Detector.image), which no bridge namespace gives"
)
CAMERA = ["CameraSensing", "Detection", "Classification"]


def renaming_line(tmp_path: Path, scan_external: bool = True) -> Path:
    """The warehouse line with the renamed camera topic; with ``scan_external`` the
    localizer's /scan is fed from outside, so a camera product's one warning is the skip."""
    line = tmp_path / "warehouse"
    shutil.copytree(WAREHOUSE, line)
    tsm = line / "warehouse.tsm"
    text = tsm.read_text(encoding="utf-8")
    cloud_image = 'topic Image : sensor_msgs/Image         name "/camera/image"'
    assert text.count(cloud_image) == 1
    text = text.replace(cloud_image, cloud_image.replace("/camera/image", "/shelf/image"))
    if scan_external:
        scan = "subscribes scan <- Scan\n"
        assert text.count(scan) == 1
        text = text.replace(scan, 'subscribes scan <- Scan external "a lidar of the site"\n')
    tsm.write_text(text, encoding="utf-8")
    return line


def validate(
    tmp_path: Path, *options: str, line: Path = WAREHOUSE
) -> tuple[int, str, str, dict[str, etree._Element]]:
    junit = tmp_path / "report.xml"
    result = CliRunner().invoke(main, ["validate", str(line), "--junit", str(junit), *options])
    document = etree.parse(str(junit))
    assert SCHEMA.validate(document), SCHEMA.error_log
    found = {case.get("name"): case for case in document.getroot().iter("testcase")}
    return result.exit_code, result.stdout, result.stderr, found


def under(stdout: str, head: str) -> list[str]:
    """The indented lines printed under the product line ``head``."""
    lines = stdout.splitlines()
    start = lines.index(head) + 1
    end = next((i for i in range(start, len(lines)) if not lines[i].startswith("    ")), None)
    return [text.removeprefix("    ") for text in lines[start:end]]


def test_an_unfed_input_is_a_warning_of_its_test_case(tmp_path):
    code, stdout, stderr, found = validate(tmp_path)
    assert code == 0 and stderr == ""
    camera = found["camera_detect"]
    assert camera.findall("failure") == []
    err = camera.findtext("system-err")
    assert (
        "warehouse.tsm:28:20: warning: Localizer.scan subscribes Amr.Scan, which no node of " in err
    )
    assert "[SPL045]" in err and "odom" not in err  # fed from outside: silent
    assert camera.find("system-out") is None  # no rehearsal: nothing else to say
    assert found["lidar_offload"].find("system-err") is None  # the rewiring feeds it
    assert under(stdout, "ok   warehouse :: camera_detect") == err.splitlines()
    assert stdout.splitlines()[-1] == "2 passed, 1 of them with warnings, 0 failed"


def test_strict_fails_the_product_with_the_warning(tmp_path):
    code, stdout, _, found = validate(tmp_path, "--strict")
    assert code == 1
    (failure,) = found["camera_detect"].findall("failure")
    assert "Localizer.scan subscribes Amr.Scan" in failure.get("message")
    assert failure.get("type") == "Warning"
    assert "[SPL045]" in failure.text
    assert found["lidar_offload"].findall("failure") == []
    assert "FAIL warehouse :: camera_detect" in stdout
    assert stdout.splitlines()[-1] == "1 passed, 1 failed"


def test_an_output_the_product_cannot_have_is_said_under_its_own_line(tmp_path):
    # was: "passed", the skip printed once after the run without the product's name
    line = renaming_line(tmp_path)
    code, stdout, stderr, found = validate(tmp_path, line=line)
    assert code == 0, stdout + stderr
    assert stderr == ""  # nothing said apart from the product it concerns
    assert under(stdout, "ok   warehouse :: camera_detect") == [SKIP]
    assert under(stdout, "ok   warehouse :: lidar_offload") == []
    assert stdout.splitlines()[-1] == "2 passed, 1 of them with warnings, 0 failed"
    assert found["camera_detect"].findtext("system-err") == SKIP
    assert found["camera_detect"].findall("failure") == []
    assert found["lidar_offload"].find("system-err") is None


def test_strict_fails_a_product_for_an_output_it_cannot_have(tmp_path):
    line = renaming_line(tmp_path)
    code, stdout, _, found = validate(tmp_path, "--strict", line=line)
    assert code == 1
    assert under(stdout, "FAIL warehouse :: camera_detect") == [SKIP]
    (failure,) = found["camera_detect"].findall("failure")
    assert (failure.get("type"), failure.get("message"), failure.text) == ("Warning", SKIP, SKIP)
    assert found["lidar_offload"].findall("failure") == []
    assert "ok   warehouse :: lidar_offload" in stdout.splitlines()
    assert stdout.splitlines()[-1] == "1 passed, 1 failed"


def resolve(line: Path, features: list[str], out: Path) -> tuple[int, str, str]:
    args = ["resolve", str(line), "--features", ",".join(features), "-o", str(out)]
    result = CliRunner().invoke(main, args)
    return result.exit_code, result.stdout, result.stderr


def test_resolve_and_validate_give_a_product_the_same_warnings_in_the_same_order(tmp_path):
    """The resolver's warnings first, then each output left out, each one line with
    ``warning:``: on spl resolve's stderr, under spl validate's line, in the test case."""
    line = renaming_line(tmp_path, scan_external=False)
    code, stdout, stderr = resolve(line, CAMERA, tmp_path / "camera")
    assert code == 0, stderr
    warnings = stderr.splitlines()
    assert len(warnings) == 2 and warnings[1] == SKIP
    assert warnings[0].startswith(f"{line / 'warehouse.tsm'}:28:20: warning: Localizer.scan")
    assert warnings[0].endswith("[SPL045]")
    assert "wrote" in stdout and "warning" not in stdout
    _, stdout, _, found = validate(tmp_path, line=line)
    assert under(stdout, "ok   warehouse :: camera_detect") == warnings
    assert found["camera_detect"].findtext("system-err").splitlines() == warnings


def test_every_product_manifest_has_one_key_set(tmp_path):
    line = renaming_line(tmp_path)
    assert resolve(line, CAMERA, tmp_path / "camera")[0] == 0
    code, _, stderr = resolve(line, ["LidarSensing", "Offload"], tmp_path / "lidar")
    assert (code, stderr) == (0, "")
    camera = json.loads((tmp_path / "camera" / "manifest.json").read_text(encoding="utf-8"))
    lidar = json.loads((tmp_path / "lidar" / "manifest.json").read_text(encoding="utf-8"))
    assert camera.keys() == lidar.keys()
    assert camera["skipped"] == {"zenoh/": SKIP.removeprefix("warning: zenoh/ not written: ")}
    assert (lidar["skipped"], lidar["warnings"], lidar["left_out"]) == ({}, [], {})
    assert not (tmp_path / "camera" / "zenoh").exists() and (tmp_path / "lidar" / "zenoh").is_dir()


def test_every_fleet_manifest_has_one_key_set(tmp_path):
    line = renaming_line(tmp_path)
    manifests = {}
    for name, features in (("camera", CAMERA), ("lidar", ["LidarSensing", "Offload"])):
        fleet = tmp_path / f"{name}.yaml"
        fleet.write_text(
            f"fleet: {name}\nproduct_line: {line.name}\nrobots:\n"
            f"  amr_1: {{features: [{', '.join(features)}]}}\n",
            encoding="utf-8",
        )
        out = tmp_path / f"{name}_fleet"
        result = CliRunner().invoke(main, ["fleet", "resolve", str(fleet), "-o", str(out)])
        assert result.exit_code == 0, result.output
        manifests[name] = json.loads((out / "fleet.json").read_text(encoding="utf-8"))
        if name == "camera":  # spl resolve's line, said of the fleet
            fleet_skip = SKIP.replace("carry this product", "carry this fleet")
            assert result.stderr.splitlines() == [fleet_skip]
        else:
            assert result.stderr == ""
    camera, lidar = manifests["camera"], manifests["lidar"]
    assert camera.keys() == lidar.keys()
    assert list(camera["skipped"]) == ["zenoh/"] and lidar["skipped"] == {}


def test_workers_and_a_cluster_report_the_warnings_of_one_job(tmp_path):
    """Forked workers and Dask workers (which load the line from a folder of their own)
    give each product the warnings, naming the user's folder, that ``--jobs 1`` and
    ``spl resolve`` give it. A third product, after the two listed, is run by a forked
    worker (the first product runs in the parent)."""
    line = renaming_line(tmp_path, scan_external=False)
    shelf = ["CameraSensing", "Detection"]  # also a client with no server: SPL046
    (line / "products" / "shelf_scan.yaml").write_text(
        f"product: shelf_scan\nfeatures: [{', '.join(shelf)}]\n", encoding="utf-8"
    )
    code, _, resolved = resolve(line, shelf, tmp_path / "shelf")
    assert code == 0 and len(resolved.splitlines()) == 3, resolved
    runs = {}
    for name, options in (
        ("one", ["--jobs", "1"]),
        ("forked", ["--jobs", "2"]),
        ("cluster", ["--scheduler", "local:1"]),
    ):
        report = tmp_path / f"{name}.xml"
        result = run_spl(["validate", str(line), "--strict", "--junit", str(report), *options])
        assert result.returncode == 1, result.stdout + result.stderr
        runs[name] = (result.stdout, report.read_bytes())
    assert runs["forked"] == runs["one"] and runs["cluster"] == runs["one"]
    stdout, report = runs["one"]
    assert under(stdout, "FAIL warehouse :: camera_detect") == [
        f"{line / 'warehouse.tsm'}:28:20: warning: Localizer.scan subscribes Amr.Scan, which "
        "no node of the product publishes [SPL045]",
        SKIP,
    ]
    assert under(stdout, "FAIL warehouse :: shelf_scan") == resolved.splitlines()
    assert "[SPL046]" in resolved.splitlines()[1]
    assert stdout.splitlines()[-1] == "1 passed, 2 failed"
    cases = {c.get("name"): c for c in etree.fromstring(report).iter("testcase")}
    assert cases["shelf_scan"].findtext("system-err") == resolved.rstrip("\n")


def test_on_a_terminal_a_product_with_warnings_is_listed_after_the_bar(tmp_path):
    """With a progress bar on the terminal only the products worth a look are listed:
    those that failed and those with warnings, each with its warnings under it."""
    line = renaming_line(tmp_path)
    terminal, bar = pty.openpty()  # stderr a terminal: the progress bar is shown
    try:
        result = subprocess.run(
            [*spl_command(), "validate", str(line)],
            stdout=subprocess.PIPE,
            stderr=bar,
            cwd=ROOT,
            text=True,
            timeout=240,
        )
    finally:
        os.close(bar)
        os.close(terminal)
    assert result.returncode == 0
    assert result.stdout.splitlines() == [
        "ok   warehouse :: camera_detect",
        f"    {SKIP}",
        "2 passed, 1 of them with warnings, 0 failed",
    ]


def test_the_configurator_shows_a_product_the_warnings_spl_resolve_prints(tmp_path):
    """``spl configure``'s architecture view reads the same warnings, in the same words."""
    from fastapi.testclient import TestClient

    from spl.configure.app import create_app
    from spl.configure.workspace import load_workspace

    line = renaming_line(tmp_path, scan_external=False)
    code, _, stderr = resolve(line, CAMERA, tmp_path / "camera")
    assert code == 0, stderr
    api = TestClient(create_app(load_workspace(line)))
    for feature in CAMERA:
        decided = api.post("/api/decide", json={"feature": feature, "action": "select"})
        assert decided.status_code == 200, decided.text
    state = api.get("/api/state").json()["states"]
    for feature, mode in state.items():
        if mode == "open":
            api.post("/api/decide", json={"feature": feature, "action": "deselect"})
    drawing = api.get("/api/architecture")
    assert drawing.status_code == 200, drawing.text
    assert drawing.json()["warnings"] == stderr.splitlines()
