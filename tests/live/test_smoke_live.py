"""``spl smoke`` with the real ROS 1 (Debian's roscore, roslaunch and rospy).

Shipped products come up green; two planted faults (a launch file remapping a
subscriber to a wrong topic, a bundle missing one bridge) fail, naming the node and
interface; Ctrl-C stops everything; and after every run no roscore, rosmaster, rosout,
roslaunch or stand-in of that run is still alive (see ``smoke_runs``).
"""

from __future__ import annotations

import json
import re
import signal
import subprocess
import time
import uuid
from pathlib import Path

import pytest

from support.smoke_runs import (
    ROOT,
    TAG,
    leftovers,
    rows_by_interface,
    run_spl,
    smoke_json,
    spl_command,
    tagged_env,
    write_product,
)

MAPPING = ROOT / "product_lines" / "mapping3d"
DATA = ROOT / "product_lines" / "data_acquisition"
PAPER = "YouBot,Stereo,AdditionalPC,Room"


@pytest.fixture(scope="module")
def paper_bundle(tmp_path_factory) -> Path:
    return write_product(MAPPING, PAPER, tmp_path_factory.mktemp("paper") / "bundle")


def test_paper_product_runs_green(paper_bundle):
    status, report = smoke_json(paper_bundle)
    assert status == 0 and report["passed"], report["failures"]
    assert report["product"] == "YouBot_Stereo_AdditionalPC_Room"
    rows = rows_by_interface(report)
    assert all(row["ok"] for row in rows.values())
    # every node of the resolved model is there, each in its container
    nodes = {(c["name"], r["node"]) for c in report["containers"] for r in c["rows"]}
    assert {("Robot", "MapOptimizer"), ("Robot", "RGBCameraL"), ("Robot", "endpoint"),
            ("MappingCloud", "VisualOdometry"), ("MappingCloud", "Database"),
            ("MappingCloud", "endpoint")} <= nodes  # fmt: skip
    assert ("MappingCloud", "MapOptimizer") not in nodes  # migrated to the robot
    # data crossed containers through the relays, from the modelled publisher
    odometry = rows["MappingCloud.VisualOdometry.rgb"]
    assert odometry["topic"] == "/camera/rgb/image"
    assert odometry["seen"].startswith("from Robot.StereoVision.rgb (")
    # a migrated node's calls reach the cloud server behind the endpoint stand-in
    calls = rows["Robot.MapOptimizer.add_keyframe"]
    assert calls["seen"].startswith("answered by MappingCloud.Database.add_keyframe (")
    # the master registered the model's types; parameters came from the launch file
    assert rows["Robot.StereoVision.rgb"]["seen"].startswith("publishes sensor_msgs/Image")
    assert rows["Robot.MapOptimizer.param CameraInfo"]["seen"] == (
        "'package://stereo_cam/calibration/stereo.yaml'"
    )


@pytest.mark.parametrize(
    "product", sorted((DATA / "products").glob("*.yaml")), ids=lambda p: p.stem
)
def test_data_acquisition_products_run_green(product, tmp_path):
    bundle = write_product(DATA, product, tmp_path / "bundle")
    status, report = smoke_json(bundle)
    assert status == 0 and report["passed"], report["failures"]
    rows = rows_by_interface(report)
    # the ROS 2 data clients take part, named and remapped as the ROS 2 launch file says
    clients = [key for key in rows if key.split(".")[1].endswith(("Writer", "Reader"))]
    assert clients and all(rows[key]["ok"] for key in clients)


def test_subscriber_remapped_to_a_wrong_topic_fails_naming_it(paper_bundle, tmp_path):
    bundle = tmp_path / "bundle"
    subprocess.run(["cp", "-r", str(paper_bundle), str(bundle)], check=True)
    launch = bundle / "ros1" / "Robot.launch"
    text = launch.read_text(encoding="utf-8")
    good = '<remap from="left" to="/stereo/left/image_raw"/>'
    assert good in text
    launch.write_text(text.replace(good, '<remap from="left" to="/stereo/left/wrong"/>'))
    status, report = smoke_json(bundle)
    assert status == 1 and not report["passed"]
    failed = [(c["name"], r["node"], r["interface"], r["topic"])
              for c in report["containers"] for r in c["rows"] if not r["ok"]]  # fmt: skip
    assert failed == [("Robot", "StereoVision", "left", "/stereo/left/image_raw"),
                      ("Robot", "StereoVision", "left", "/stereo/left/wrong")]  # fmt: skip
    assert any("Robot.StereoVision.left (/stereo/left/image_raw): expected from "
               "RGBCameraL.image; seen nothing received; bound to /stereo/left/wrong" in f
               for f in report["failures"])  # fmt: skip
    assert any("(/stereo/left/wrong): subscribes sensor_msgs/Image, not in the model" in f
               for f in report["failures"])  # fmt: skip


def test_a_bridge_missing_from_the_model_is_a_modelled_gap_not_a_failure(paper_bundle, tmp_path):
    """Without the bridge the model itself leaves the odometry unfed (resolve warns,
    SPL045): the rehearsal says so and relays nothing there, but it is no failed
    rehearsal; data arriving there anyway would be one."""
    bundle = tmp_path / "bundle"
    subprocess.run(["cp", "-r", str(paper_bundle), str(bundle)], check=True)
    model = bundle / "resolved.tsm"
    bridge = "bridge Robot.RGBImg -> MappingCloud.RGBImg\n"
    text = model.read_text(encoding="utf-8")
    assert bridge in text
    model.write_text(text.replace(bridge, ""), encoding="utf-8")
    status, report = smoke_json(bundle)
    assert status == 0 and report["passed"], report["failures"]
    rgb = rows_by_interface(report)["MappingCloud.VisualOdometry.rgb"]
    assert (rgb["expected"], rgb["seen"], rgb["ok"]) == (
        "nothing: unfed in the model (SPL045)",
        "nothing received",
        True,
    )


def test_without_ros_exits_2_with_the_packages_to_install(paper_bundle, tmp_path):
    (tmp_path / "bin").mkdir()  # a PATH with no roscore
    result = run_spl(["smoke", str(paper_bundle)], PATH=str(tmp_path / "bin"))
    assert result.returncode == 2
    assert result.stderr == (
        "error: roscore not found: apt-get install ros-core python3-rospy "
        "python3-roslaunch python3-rostopic\n"
    )
    result = run_spl(["validate", str(MAPPING), "--smoke"], PATH=str(tmp_path / "bin"))
    assert result.returncode == 2 and "roscore not found" in result.stderr


@pytest.mark.parametrize("command", ["smoke", "validate --smoke"])
def test_ctrl_c_stops_every_process(paper_bundle, tmp_path, command):
    """Ctrl-C as a terminal sends it (to the whole foreground process group), while the
    graph is up: exit 130, no process left, temporary folders removed."""
    import os

    tag = uuid.uuid4().hex
    if command == "smoke":
        args, expected = ["smoke", str(paper_bundle)], 1
    else:
        line = str(ROOT / "tests" / "models" / "launch")
        args, expected = ["validate", line, "--all", "--smoke", "--jobs", "2"], 3
    (tmp_path / "tmp").mkdir()
    process = subprocess.Popen(
        [*spl_command(), *args], env=tagged_env(tag, TMPDIR=str(tmp_path / "tmp")),
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
    )  # fmt: skip
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:  # until masters and stand-ins of every run are up
        running = leftovers(tag)
        if sum("standin.py" in c for c in running) >= expected:
            break
        time.sleep(0.1)
    assert any("rosmaster" in c for c in running)
    os.killpg(process.pid, signal.SIGINT)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 130, err
    assert "interrupted" in err and "Traceback" not in err
    # SIGKILLed processes of a busy machine may take a moment to leave /proc
    assert leftovers(tag, wait=5.0) == []
    assert list((tmp_path / "tmp").iterdir()) == []


def test_validate_smoke_reports_each_product_in_junit(tmp_path):
    """The launch test line: 'Fleet' alone leaves Navigator.map without a publisher: the
    resolver warns (SPL045) and the rehearsal, finding that modelled gap live too, passes
    (it fails only where the model says data flows and it did not); the JUnit case
    carries the warning."""
    junit = tmp_path / "report.xml"
    line = ROOT / "tests" / "models" / "launch"
    result = run_spl(["validate", str(line), "--all", "--smoke", "--jobs", "2",
                      "--junit", str(junit)])  # fmt: skip
    assert result.returncode == 0, result.stdout + result.stderr
    from lxml import etree

    cases = {c.get("name"): c for c in etree.parse(str(junit)).iter("testcase")}
    assert sorted(cases) == ["CloudMapping", "CloudMapping,OnboardSlam", "Fleet"]
    assert all(case.find("failure") is None for case in cases.values())
    fleet = cases["Fleet"].findtext("system-err")  # warnings, as spl resolve's stderr
    assert "Navigator.map subscribes Scout.MapView, which no node of the product publishes" in fleet
    assert "[SPL045]" in fleet
    for name in cases:
        assert "smoke: all " in cases[name].findtext("system-out")
    assert "3 passed, 1 of them with warnings, 0 failed" in result.stdout  # Fleet's SPL045


def test_a_master_it_did_not_start_is_never_used(tmp_path, monkeypatch):
    """When the port picked for a container's roscore is taken by someone else's master
    (ours then refuses to start), the rehearsal starts its own on another port and
    leaves the foreign master untouched."""
    import os

    from spl.smoke import rehearsal
    from spl.smoke.live import Master
    from spl.smoke.processes import free_port

    bundle = write_product(ROOT / "tests" / "models" / "launch", "CloudMapping", tmp_path / "b")
    port = free_port()
    foreign = subprocess.Popen(
        ["rosmaster", "--core", "-p", str(port)],
        env={**os.environ, "ROS_HOME": str(tmp_path / "foreign")},
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
    )  # fmt: skip
    try:
        master = Master(f"http://127.0.0.1:{port}/")
        deadline = time.monotonic() + 30
        while master.pid() != foreign.pid and time.monotonic() < deadline:
            time.sleep(0.1)
        assert master.pid() == foreign.pid
        picks = iter([port])
        given = []

        def pick() -> int:
            given.append(next(picks, None) or free_port())
            return given[-1]

        monkeypatch.setattr(rehearsal, "free_port", pick)
        tag = uuid.uuid4().hex
        monkeypatch.setenv(TAG, tag)
        result = rehearsal.run_smoke(bundle, timeout=90)
        assert result.passed, result.failures()
        assert len(given) == 3 and given[0] == port  # two containers, one started again
        assert leftovers(tag) == []
        assert master.graph().nodes() == set()  # nothing of the rehearsal came here
    finally:
        foreign.kill()
        foreign.wait()


def test_a_node_that_dies_is_reported_without_waiting_for_the_timeout(tmp_path):
    """A launch file edited to give a node a prefix that ends it at once: roslaunch
    reports the death, the rehearsal names the node and does not wait for --timeout."""
    bundle = write_product(ROOT / "tests" / "models" / "launch", "CloudMapping", tmp_path / "b")
    launch = bundle / "ros1" / "Scout.launch"
    text = launch.read_text(encoding="utf-8")
    node = '<node pkg="nav_stack" type="navigator" name="Navigator" ns="/scout">'
    assert node in text
    launch.write_text(text.replace(node, node[:-1] + ' launch-prefix="false">'))
    status, report = smoke_json(bundle, "--timeout", "120")
    assert status == 1
    assert report["failures"][0] == "roslaunch-Scout: node scout/Navigator ended, roslaunch reports"
    failed = {(c["name"], r["node"]) for c in report["containers"] for r in c["rows"]
              if not r["ok"]}  # fmt: skip
    assert failed == {("Scout", "Navigator")}
    assert report["seconds"] < 100  # a verdict once the graph is quiet, not at the timeout


def test_a_killed_validate_leaves_no_worker_nor_rehearsal(tmp_path):
    """SIGKILL (a CI timeout) reaches only spl itself: its forked workers and their
    rehearsals follow it through the parent-death signal instead of idling for ever."""
    import os

    tag = uuid.uuid4().hex
    line = str(ROOT / "tests" / "models" / "launch")
    process = subprocess.Popen(
        [*spl_command(), "validate", line, "--all", "--smoke", "--jobs", "2"],
        env=tagged_env(tag), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:  # until forked workers rehearse
        running = leftovers(tag)
        workers = sum(" validate " in c for c in running) - 1
        if workers >= 1 and any("standin.py" in c for c in running):
            break
        time.sleep(0.1)
    os.kill(process.pid, signal.SIGKILL)
    process.wait()
    # without the parent-death signal the rehearsal runs on to its verdict (5 s and more)
    assert leftovers(tag, wait=3.0) == []


@pytest.mark.parametrize(
    "script",
    [
        "exit 3",  # never comes up: started again, then reported
        # serves its container until roslaunch has started Navigator there, then ends
        'roscore "$@" & core=$!\n'
        "until rosnode list 2>/dev/null | grep -q Navigator; do sleep 0.2; done\n"
        "kill -INT $core; wait $core; exit 3",
    ],
    ids=["at-once", "mid-run"],
)
def test_a_roscore_that_ends_is_a_failed_rehearsal_not_an_internal_error(tmp_path, script):
    """A master that ends (another program took its port, an OOM kill) fails the
    rehearsal, named, without waiting for the timeout; it used to be ``internal error:
    KeyError: 'roscore-Scout'``. Navigator listens on a wrong topic, so the rehearsal
    cannot pass before Scout's master is gone."""
    import os
    import shutil

    bundle = write_product(ROOT / "tests" / "models" / "launch", "CloudMapping", tmp_path / "b")
    launch = bundle / "ros1" / "Scout.launch"
    good = '<remap from="scan" to="/scan"/>\n    <remap from="map"'
    text = launch.read_text(encoding="utf-8")
    assert good in text
    launch.write_text(text.replace(good, good.replace("/scan", "/wrong")))
    fake = tmp_path / "bin"
    fake.mkdir()
    real = shutil.which("roscore")
    assert real is not None
    (fake / "roscore").write_text(f"#!/bin/sh\nPATH={Path(real).parent}:$PATH\n{script}\n")
    (fake / "roscore").chmod(0o755)
    result = run_spl(["smoke", str(bundle), "--json", "--timeout", "90"],
                     PATH=f"{fake}{os.pathsep}{os.environ['PATH']}")  # fmt: skip
    assert result.returncode == 1, result.stderr
    assert "internal error" not in result.stdout + result.stderr
    failures = json.loads(result.stdout)["failures"]
    # at once, whichever master used up the restarts is named; mid-run, Scout's
    ended = re.compile(r"roscore-(Scout|Mapping) exited with status 3" if script == "exit 3"
                       else r"roscore-Scout exited with status 3")  # fmt: skip
    assert any(ended.match(f) for f in failures), failures
    assert json.loads(result.stdout)["seconds"] < 80  # not the timeout
