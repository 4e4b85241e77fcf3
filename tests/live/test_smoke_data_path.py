"""spl smoke runs the data path of a data-acquisition bundle for real: the generated
service (uvicorn, SQLite, the transformer), the generated ROS 1 writers and readers
(rospy, started by the bundle's own launch files), stand-ins only for the robots' own
nodes; values are checked end to end against the model's transforms, through a SIGKILL
and restart of a service."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from support.smoke_runs import ROOT, rows_by_interface, run_spl, smoke_json, write_product

DATA = ROOT / "product_lines" / "data_acquisition"


@pytest.fixture(scope="module")
def both(tmp_path_factory) -> Path:
    """Both case studies of the data-acquisition paper: GPS seconds to degrees, velocities
    to commands
    (whose reader subscribes over a WebSocket)."""
    return write_product(DATA, "Positions,Follow,Embedded", tmp_path_factory.mktemp("d") / "b")


def test_the_generated_nodes_service_and_transformer_move_the_data_end_to_end(both):
    status, report = smoke_json(both)
    assert status == 0 and report["passed"], report["failures"]
    assert report["skipped"] is None
    rows = rows_by_interface(report)
    # the generated nodes run (registered on their masters), not stand-ins
    assert rows["Rover.PositionWriter.records"]["expected"].endswith("(generated node)")
    assert rows["EV3B.CommandReader.records"]["seen"] == "publishes ev3_msgs/Command"
    # every value sent is stored once, in order, through the service's kill and restart
    assert rows["DataCloud.PositionStore.stored from PositionWriter"]["seen"] == "12 stored"
    assert rows["DataCloud.PositionStore.fault round"]["seen"].startswith("killed (SIGKILL) after")
    # refined as the .tsm says: lat / 3600; each velocity's duration is the time to the
    # next one, so the last waits for a next record
    assert rows["DataCloud.PositionStore.refined PositionInDEG"]["seen"] == "12 refined"
    assert rows["DataCloud.FollowStore.refined Command"]["seen"] == "11 refined"
    # and received by the readers' subscribers once each, in order: the subscribing
    # CommandReader by EV3B's CommandFollower, the polling PositionReader by the
    # rehearsal's probe (no node of the product listens to /gps/deg)
    ev3b = next(c for c in report["containers"] if c["name"] == "EV3B")["rows"]
    assert any(r["seen"] == "11 received" and r["ok"] for r in ev3b)
    rover = next(c for c in report["containers"] if c["name"] == "Rover")["rows"]
    probe = [r for r in rover if r["node"] == "spl_probe_PositionReader"]
    assert [r["seen"] for r in probe][1:] == ["12 received"] and all(r["ok"] for r in probe)
    assert probe[0]["seen"].startswith("from PositionReader.records (")


def test_a_transform_changed_by_hand_in_the_generated_service_fails(both, tmp_path):
    bundle = tmp_path / "bundle"
    shutil.copytree(both, bundle)
    (transforms,) = bundle.glob("services/PositionStore/*/transforms.py")
    text = transforms.read_text()
    assert "_div(current['lat'], 3600.0)" in text
    transforms.write_text(
        text.replace("_div(current['lat'], 3600.0)", "_div(current['lat'], 3601.0)")
    )
    status, report = smoke_json(bundle)
    assert status == 1 and not report["passed"]
    (failure,) = report["failures"]
    assert failure.startswith(
        "DataCloud.PositionStore.refined PositionInDEG (/PositionStore/PositionInDEG): "
        "expected SecondToDEG of each stored record (12); seen 12 refined;"
    )
    assert "raw 1: [0.0009025270758122744, " in failure  # 3.25 / 3601, not 3.25 / 3600


def test_a_service_that_cannot_start_here_is_said_and_stood_in_for(both, tmp_path):
    bundle = tmp_path / "bundle"
    shutil.copytree(both, bundle)
    for app in bundle.glob("services/*/*/app.py"):
        app.write_text("import fastapi_that_is_not_installed\n")
    result = run_spl(["smoke", str(bundle), "--timeout", "90"])
    assert result.returncode == 0, result.stdout + result.stderr
    (warning,) = [line for line in result.stderr.splitlines() if line.startswith("warning: ")]
    assert warning.startswith(
        "warning: data path not rehearsed: the generated PositionStore service does not start"
    )
    assert "No module named 'fastapi_that_is_not_installed'" in warning
    assert "(generated node)" not in result.stdout  # the writers and readers are stand-ins
