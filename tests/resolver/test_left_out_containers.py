"""A container left with no node (and no store) after pruning is not deployed.

The regression: an orchard product without Scouting got ``ros1/Scout.launch`` and
``ros2/Scout.launch.xml`` with no node, ``rapyuta/Scout.json`` with credentials and
nothing else, and a Zenoh bridge configuration for a robot that runs nothing. A
robotics engineer reads a product's bundle as "what to deploy": such a robot is not
part of the product. Every target leaves it out, and the manifest, the resolve summary
and ``spl explain`` say it was left out and why.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file, selection_from_list

from support.cli_outcome import run

ORCHARD = Path(__file__).resolve().parents[2] / "product_lines" / "orchard"
REASON = "robot container left with no node in this product: not deployed"

TSM = """system Survey

robot container Rover {
    endpoint robot_id "rover_1" url "wss://cloud.example.org:9000/" user "rover"
             password env "RCE_PASSWORD"
    topic Scan : sensor_msgs/LaserScan name "/scan"
    node Lidar {
        implementation urg_node/urg_node
        publishes scan -> Scan
    }
}

robot container Drone {
    endpoint robot_id "drone_1" url "wss://cloud.example.org:9000/" user "drone"
             password env "RCE_PASSWORD"
    topic Photo : sensor_msgs/Image name "/photo"
    optional node Camera {
        implementation usb_cam/usb_cam_node
        publishes image -> Photo
    }
}

cloud container SurveyCloud {
    topic Scan  : sensor_msgs/LaserScan name "/rover/scan"
    topic Photo : sensor_msgs/Image     name "/drone/photo"
    node Mapper {
        implementation survey/mapper
        subscribes scan <- Scan
    }
    optional node Mosaic {
        implementation survey/mosaic
        subscribes photo <- Photo
    }
}

bridge Rover.Scan -> SurveyCloud.Scan
bridge Drone.Photo -> SurveyCloud.Photo
"""
FM = """feature model Survey
root Survey {
    optional Aerial
}
"""
RM = """resolution model Survey
tsm "survey.tsm"
fm "survey.fm"

when Aerial selected {
    require Drone.Camera, Mosaic
}
"""


@pytest.fixture(scope="module")
def survey(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("survey")
    for name, text in (("survey.tsm", TSM), ("survey.fm", FM), ("survey.rm", RM)):
        (folder / name).write_text(text, encoding="utf-8")
    return folder


def bundle(folder: Path, features: str) -> dict[str, bytes]:
    product = resolve(load_product_line(folder), selection_from_list(features)).product
    return build_bundle(product, BundleOptions(render_diagrams=False)).files


def mentions(files: dict[str, bytes], *words: str) -> list[str]:
    """The bundle files whose path or text names any of ``words``."""
    return sorted(
        path
        for path, data in files.items()
        if path != "manifest.json" and any(word in path or word.encode() in data for word in words)
    )


def test_a_robot_without_nodes_is_in_no_target(survey: Path) -> None:
    files = bundle(survey, "Survey")
    assert mentions(files, "Drone", "drone_1") == []
    assert sorted(p for p in files if p.startswith(("ros1/", "ros2/", "rapyuta/"))) == [
        "rapyuta/Rover.json",
        "ros1/Rover.launch",
        "ros1/SurveyCloud.launch",
        "ros2/Rover.launch.xml",
        "ros2/SurveyCloud.launch.xml",
    ]
    assert "zenoh/rover_1.json5" in files
    manifest = json.loads(files["manifest.json"])
    assert manifest["left_out"] == {"Drone": REASON}
    assert "Drone" not in manifest["placement"].values()


def test_the_robot_is_deployed_when_a_feature_uses_it(survey: Path) -> None:
    files = bundle(survey, "Survey,Aerial")
    for path in ("ros1/Drone.launch", "ros2/Drone.launch.xml"):
        assert b'pkg="usb_cam"' in files[path], path
    assert b'"drone_1/sub_Photo"' in files["rapyuta/Drone.json"]
    assert "zenoh/drone_1.json5" in files
    assert any(b"drone_1" in files[p] for p in files if p.startswith("kubernetes/"))
    assert json.loads(files["manifest.json"])["left_out"] == {}  # one key set for all


def test_summary_and_explain_say_it_was_left_out(survey: Path, tmp_path: Path) -> None:
    resolved = run("resolve", survey, "--features", "Survey", "-o", tmp_path / "out")
    assert resolved.exit_code == 0, resolved.output
    assert f"  left out: Drone ({REASON})" in resolved.stdout
    assert not (tmp_path / "out" / "ros1" / "Drone.launch").exists()
    explained = run("explain", survey, "--features", "Survey", "Drone")
    assert explained.exit_code == 0, explained.output
    assert f"Drone: removed: {REASON}" in explained.stdout


def test_orchard_without_scouting_deploys_no_scout() -> None:
    """The shipped line: the product that found the defect."""
    line = load_product_line(ORCHARD)
    selection = load_selection_file(ORCHARD / "products" / "cloud_vacuum.yaml")
    files = build_bundle(
        resolve(line, selection).product, BundleOptions(render_diagrams=False)
    ).files
    for path in ("ros1/Scout.launch", "ros2/Scout.launch.xml", "rapyuta/Scout.json"):
        assert path not in files
    assert mentions(files, "scout_1", "Scout") == []
    assert json.loads(files["manifest.json"])["left_out"] == {"Scout": REASON}
