"""Every shipped product's bundle validates artifact by artifact; broken bundles do not."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from spl.dsl.tsm.language import parse_text
from spl.generators.bundle.validation import validate_bundle
from spl.generators.bundle.writer import bundle_files
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file

LINES = Path(__file__).resolve().parents[2] / "product_lines"
PRODUCTS = sorted(LINES.glob("*/products/*.yaml"))


@pytest.fixture(scope="module")
def lines():
    return {path.name: load_product_line(path) for path in LINES.iterdir() if path.is_dir()}


def bundle(lines, product: Path) -> dict[str, bytes]:
    line = lines[product.parent.parent.name]
    return bundle_files(resolve(line, load_selection_file(product)).product)


@pytest.mark.parametrize("product", PRODUCTS, ids=lambda p: f"{p.parent.parent.name}/{p.stem}")
def test_shipped_product_bundle_validates(lines, product):
    files = bundle(lines, product)
    assert validate_bundle(files) == []
    # what spl validate no longer re-parses per product: the printed model reads back
    parse_text(files["resolved.tsm"].decode("utf-8"), "resolved.tsm")
    kinds = {path.split("/")[0] for path in files}
    assert {"ros1", "ros2", "rapyuta", "manifest.json", "resolved.tsm", "architecture.svg"} <= kinds


def test_paper_product_bundle_contents(lines):
    files = bundle(lines, LINES / "mapping3d" / "products" / "youbot_stereo_room.yaml")
    robot_launch = files["ros1/Robot.launch"].decode()
    assert 'name="MapOptimizer"' in robot_launch and "DepthCamera" not in robot_launch
    assert 'name="MapOptimizer"' not in files["ros2/MappingCloud.launch.xml"].decode()
    config = json.loads(files["rapyuta/Robot.json"])
    robot_interfaces = {
        i["iTag"]: i["iType"] for i in config["interfaces"] if i["eTag"] == config["robotID"]
    }
    assert robot_interfaces == {
        "sub_RGBImg": "SubscriberConverter",
        "sub_DepthImg": "SubscriberConverter",
        "pub_Keyframes": "PublisherConverter",
        "sub_PoseUpdated": "SubscriberConverter",
        "srv_Database_add_keyframe": "ServiceProviderConverter",
        "srv_Database_update_poses": "ServiceProviderConverter",
        "srv_StrategyPlanner_next_target": "ServiceProviderConverter",
    }
    assert config["password"] == "${RCE_PASSWORD}"


@pytest.mark.parametrize(
    ("path", "damage", "expected"),
    [
        ("ros1/Robot.launch", lambda b: b.replace(b'pkg="', b'package="', 1), "ros1/Robot.launch:"),
        (
            "ros2/Robot.launch.xml",
            lambda b: b.replace(b"<node ", b"<nod ", 1),
            "ros2/Robot.launch.xml:",
        ),
        ("rapyuta/Robot.json", lambda b: b.replace(b"sub_RGBImg", b"sub_Nothing", 1), "Robot.json"),
    ],
)
def test_broken_bundles_are_rejected(lines, path, damage, expected):
    files = bundle(lines, LINES / "mapping3d" / "products" / "youbot_stereo_room.yaml")
    files[path] = damage(files[path])
    problems = validate_bundle(files)
    assert any(p.startswith(expected) for p in problems if "sha256" not in p), problems
    assert f"manifest.json: sha256 of {path} does not match" in problems


def test_broken_generated_python_is_rejected(lines):
    files = bundle(lines, LINES / "data_acquisition" / "products" / "positions_embedded.yaml")
    app = next(p for p in files if p.endswith("/app.py"))
    files[app] += b"\ndef broken(:\n"
    assert any(p.startswith(app) for p in validate_bundle(files))
