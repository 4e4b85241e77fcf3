"""Rapyuta files of parsed models and of the shipped mapping3d products: the engine's
schema and rules accept them, and the placement is the one the case study describes."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from spl.dsl.tsm import language as tsm_language
from spl.generators.rapyuta.configurations import generate
from spl.generators.rapyuta.rules import check_all
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file, selection_from_list

ROOT = Path(__file__).parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"
TWO_ROBOTS = Path(__file__).parents[1] / "models" / "rapyuta" / "two_robots.tsm"


def accepted(files, *paths):
    """Problems of the named files (all when none named), schema and rules together."""
    paths = paths or tuple(files)
    return [
        str(p)
        for p in check_all(
            [json.loads(files[path]) for path in paths], [path.split("/")[1] for path in paths]
        )
    ]


def connections(doc):
    return [f"{c['tagA']} -> {c['tagB']}" for c in doc.get("connections", [])]


@pytest.fixture(scope="module")
def mapping_line():
    return load_product_line(MAPPING)


def test_template_of_mapping3d_parses_and_generates_an_accepted_file():
    system = tsm_language.parse_file(MAPPING / "mapping.tsm")
    cloud = next(c for c in system.containers if c.name == "MappingCloud")
    planner = next(n for n in cloud.nodes if n.name == "StrategyPlanner")
    planner.package, planner.executable = "exploration", "room_strategy"  # as 'Room' would
    files = generate(ResolvedProduct(name="template", system=system, features=()))
    assert accepted(files) == []
    doc = json.loads(files["rapyuta/Robot.json"])
    # every node of the template is private: one container for this robot
    assert doc["containers"] == [{"cTag": "MappingCloud_robot_1"}]
    assert len(doc["nodes"]) == 5
    assert "parameters" not in doc  # CameraInfo is left to a feature in the template
    assert connections(doc) == [
        "MappingCloud_robot_1/sub_PoseUpdated -> robot_1/pub_PoseUpdated",
        "robot_1/srv_StrategyPlanner_next_target -> "
        "MappingCloud_robot_1/cli_StrategyPlanner_next_target",
        "robot_1/sub_DepthImg -> MappingCloud_robot_1/pub_DepthImg",
        "robot_1/sub_RGBImg -> MappingCloud_robot_1/pub_RGBImg",
    ]


@pytest.mark.parametrize("selection", sorted(p.name for p in (MAPPING / "products").glob("*.yaml")))
def test_every_shipped_mapping3d_product_is_accepted(mapping_line, selection):
    product = resolve(mapping_line, load_selection_file(MAPPING / "products" / selection)).product
    files = generate(product)
    assert list(files) == ["rapyuta/Robot.json"]
    assert accepted(files) == []
    assert generate(product) == files


def test_the_papers_product_mirrors_the_migrated_map_optimizer(mapping_line):
    # the mapping paper's Fig. 5: YouBot, Stereo, AdditionalPC, Room; MapOptimizer on the robot
    product = resolve(mapping_line, selection_from_list("YouBot,Stereo,AdditionalPC,Room"))
    doc = json.loads(generate(product.product)["rapyuta/Robot.json"])
    assert [(n["cTag"], n["nTag"]) for n in doc["nodes"]] == [
        ("MappingCloud_mappers", "Database"),
        ("MappingCloud_mappers", "MapMerger"),
        ("MappingCloud_mappers", "StrategyPlanner"),
        ("MappingCloud_robot_1", "VisualOdometry"),
    ]
    assert connections(doc) == [
        "MappingCloud_robot_1/sub_Keyframes -> robot_1/pub_Keyframes",
        "robot_1/srv_Database_add_keyframe -> MappingCloud_mappers/cli_Database_add_keyframe",
        "robot_1/srv_Database_update_poses -> MappingCloud_mappers/cli_Database_update_poses",
        "robot_1/srv_StrategyPlanner_next_target -> "
        "MappingCloud_mappers/cli_StrategyPlanner_next_target",
        "robot_1/sub_DepthImg -> MappingCloud_robot_1/pub_DepthImg",
        "robot_1/sub_PoseUpdated -> MappingCloud_mappers/pub_PoseUpdated",
        "robot_1/sub_RGBImg -> MappingCloud_robot_1/pub_RGBImg",
    ]


def test_two_robots_of_a_group_parsed_from_tsm():
    system = tsm_language.parse_file(TWO_ROBOTS)
    files = generate(ResolvedProduct(name="two", system=system, features=()))
    assert list(files) == ["rapyuta/Alpha.json", "rapyuta/Beta.json"]
    # together; Alpha's on its own (it declares the shared containers); Beta's needs
    # Alpha's: it connects to the shared containers' interfaces Alpha's file declares
    assert accepted(files) == []
    assert accepted(files, "rapyuta/Alpha.json") == []
    refused = accepted(files, "rapyuta/Beta.json")
    assert refused and all(
        "[unresolved-tag]" in p and ("MappingCloud_mappers/" in p or "MappingCloud_public/" in p)
        for p in refused
    )
    alpha, beta = (json.loads(files[p]) for p in files)

    def shared(doc):
        tags = {"MappingCloud_mappers", "MappingCloud_public"}
        return {
            key: [e for e in doc[key] if e.get("cTag", e.get("eTag")) in tags]
            for key in ("containers", "nodes", "parameters", "interfaces")
        }

    assert shared(beta) == {key: [] for key in shared(beta)}  # declared once, by Alpha
    assert shared(alpha)["containers"] == [
        {"cTag": "MappingCloud_mappers", "cpu": 4, "group": "mappers", "memory": 4096, "size": 2},
        {"cTag": "MappingCloud_public", "cpu": 4, "memory": 4096, "size": 2},
    ]
    assert alpha["containers"][0] == {
        "cTag": "MappingCloud_alpha",
        "cpu": 4,
        "memory": 4096,
        "size": 2,
    }
    assert beta["containers"][0]["cTag"] == "MappingCloud_beta"
    assert [p["value"] for p in alpha["parameters"]] == [
        "package://rapyuta_mapping/cam/default.yaml",
        20,
        15.0,
        True,
    ]
    assert connections(beta) == [
        "MappingCloud_beta/srv_Database_add_keyframe -> "
        "MappingCloud_mappers/cli_Database_add_keyframe",
        "MappingCloud_beta/sub_PoseUpdated -> MappingCloud_mappers/pub_PoseUpdated",
        "MappingCloud_beta/sub_PoseUpdated -> beta/pub_PoseUpdated",
        "beta/srv_StrategyPlanner_next_target -> "
        "MappingCloud_mappers/cli_StrategyPlanner_next_target",
        "beta/sub_RGBImg -> MappingCloud_beta/pub_RGBImg",
    ]
    # the bridge between the two shared containers is made once, by Alpha's file
    between = (
        "MappingCloud_public/srv_Database_get_map -> MappingCloud_mappers/cli_Database_get_map"
    )
    assert between in connections(alpha)
    own = [c.replace("alpha", "beta") for c in connections(alpha) if c != between]
    assert own == connections(beta)


ORCHARD = ROOT / "product_lines" / "orchard"
YIELD_PUBLIC = ORCHARD / "products" / "scout_yield_public.yaml"


def test_orchard_robots_share_one_yield_map_declared_once():
    # Harvester and Scout log in as one user: the public yield map is one instance,
    # declared by the first robot's file (by name) and used by the other's
    product = resolve(load_product_line(ORCHARD), load_selection_file(YIELD_PUBLIC)).product
    assert not [w for w in product.warnings if w.code == "SPL047"]
    files = generate(product)
    assert accepted(files) == []
    harvester, scout = (json.loads(files[f"rapyuta/{r}.json"]) for r in ("Harvester", "Scout"))
    assert "OrchardCloud_public" in [c["cTag"] for c in harvester["containers"]]
    assert "OrchardCloud_public" not in [c["cTag"] for c in scout["containers"]]
    assert any("OrchardCloud_public/" in c for c in connections(scout))


def test_robots_of_two_users_each_declare_their_users_instance_and_are_warned(tmp_path):
    # the engine keeps each user's containers apart: with the Scout logging in as a user
    # of its own, each file declares its own user's instance and connects only to it, and
    # the product says the robots share nothing on Rapyuta
    line = tmp_path / "orchard"
    shutil.copytree(ORCHARD, line)
    tsm_file = line / "orchard.tsm"
    text = tsm_file.read_text()
    scout = 'robot_id "scout_1" url "wss://orchard.example.org:9000/" user "orchard"'
    assert scout in text
    tsm_file.write_text(text.replace(scout, scout.replace('"orchard"', '"scout"')))
    selection = load_selection_file(line / "products" / YIELD_PUBLIC.name)
    product = resolve(load_product_line(line), selection).product
    [warning] = [w for w in product.warnings if w.code == "SPL047"]
    cloud_line = next(i for i, t in enumerate(text.splitlines(), 1) if "cloud container" in t)
    assert (warning.location.file, warning.location.line) == (str(tsm_file), cloud_line)
    assert warning.severity == "warning"
    assert "(YieldMapper) run in one instance, OrchardCloud_public, for robots " in warning.message
    assert "harvester_03 (user 'orchard'), scout_02 (user 'scout')" in warning.message
    files = generate(product)
    assert accepted(files) == []
    for path in files:
        document = json.loads(files[path])
        assert "OrchardCloud_public" in [c["cTag"] for c in document["containers"]], path
        assert accepted(files, path) == []  # needs nothing from another user's file
