"""Node migration with endpoint rewiring (docs/resolution.md) on a small dedicated line:
robot->cloud, cloud->robot and cloud->cloud, for publishers, subscribers, service
servers and clients, with hairpin removal, topic reuse and no duplicate bridges."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.architecture_view import view

LINE = Path(__file__).parents[1] / "models" / "resolver" / "migrations"


@pytest.fixture(scope="module")
def line():
    return load_product_line(LINE)


def resolved(line, features: str):
    return resolve(line, selection_from_list(features)).product


def test_without_migration_the_template_wiring_is_kept(line):
    v = view(resolved(line, "Test").system)
    assert v["bridges"] == [
        "Cloud.endpoint.sub_Pose -> Archive.endpoint.pub_Pose",
        "Cloud.endpoint.sub_Pose -> Robot.endpoint.pub_Pose",
        "Robot.endpoint.srv_Planner_plan -> Cloud.endpoint.cli_Planner_plan",
        "Robot.endpoint.sub_Filtered -> Cloud.endpoint.pub_Filtered",
    ]
    assert v["bindings"]["Navigator.plan"] == "Robot.endpoint.srv_Planner_plan"


def test_robot_to_cloud_publisher_and_subscriber(line):
    product = resolved(line, "MoveFilter")
    v = view(product.system)
    assert v["placement"]["Filter"] == "Cloud"
    # the subscriber gets a new topic in the cloud, fed from the robot's /scan
    assert v["bindings"]["Filter.scan"] == "Cloud.Scan"
    assert "Robot.endpoint.sub_Scan -> Cloud.endpoint.pub_Scan" in v["bridges"]
    # the publisher reuses the cloud's same-named topic: Mapper is served locally and the
    # robot->cloud bridge that only carried Filter's output is gone (no hairpin)
    assert v["bindings"]["Filter.filtered"] == "Cloud.Filtered"
    assert not any("Filtered" in b for b in v["bridges"])
    assert "Filtered" not in v["topics"]["Robot"]
    assert [(m.node, m.source, m.target) for m in product.migrations] == [
        ("Filter", "Robot", "Cloud")
    ]


def test_cloud_to_robot_with_local_peers_and_shared_stand_in(line):
    v = view(resolved(line, "MoveMapper").system)
    assert v["placement"]["Mapper"] == "Robot"
    # peers already on the robot are wired locally, both bridges that served them go
    assert v["bindings"]["Mapper.filtered"] == "Robot.Filtered"
    assert v["bindings"]["Mapper.pose"] == "Robot.Pose"
    assert v["bindings"]["Navigator.pose"] == "Robot.Pose"
    # the archive now gets /pose straight from the robot, not through the cloud
    assert "Robot.endpoint.sub_Pose -> Archive.endpoint.pub_Pose" in v["bridges"]
    assert not any(b.startswith("Cloud.endpoint.sub_Pose") for b in v["bridges"])
    assert v["topics"]["Cloud"] == []
    # both robot clients share one stand-in for the cloud planner: one connection
    assert v["bindings"]["Mapper.plan"] == "Robot.endpoint.srv_Planner_plan"
    assert v["bindings"]["Navigator.plan"] == "Robot.endpoint.srv_Planner_plan"
    assert (
        v["bridges"].count("Robot.endpoint.srv_Planner_plan -> Cloud.endpoint.cli_Planner_plan")
        == 1
    )
    assert len(v["bridges"]) == 2


def test_service_server_migration_rewires_clients_both_ways(line):
    v = view(resolved(line, "MovePlanner").system)
    assert v["placement"]["Planner"] == "Robot"
    # the robot client that reached the planner through the endpoints now calls it locally
    assert v["bindings"]["Navigator.plan"] == "Planner.plan"
    assert "ServiceServer:srv_Planner_plan" not in v["endpoints"]["Robot"]
    # the cloud client gets a stand-in in the cloud calling the robot's planner
    assert v["bindings"]["Mapper.plan"] == "Cloud.endpoint.srv_Planner_plan"
    assert "Cloud.endpoint.srv_Planner_plan -> Robot.endpoint.cli_Planner_plan" in v["bridges"]


def test_cloud_to_cloud_and_empty_container_removed(line):
    v = view(resolved(line, "MoveRecorder").system)
    assert v["placement"]["Recorder"] == "Cloud"
    assert v["bindings"]["Recorder.pose"] == "Cloud.Pose"
    assert "Archive" not in v["topics"]
    assert not any("Archive" in b for b in v["bridges"])


def test_two_migrations_swap_sides(line):
    v = view(resolved(line, "MoveFilter,MoveMapper").system)
    assert v["placement"]["Filter"] == "Cloud" and v["placement"]["Mapper"] == "Robot"
    assert "Robot.endpoint.sub_Scan -> Cloud.endpoint.pub_Scan" in v["bridges"]
    assert "Cloud.endpoint.sub_Filtered -> Robot.endpoint.pub_Filtered" in v["bridges"]
    assert v["bindings"]["Mapper.filtered"] == "Robot.Filtered"
    assert len([b for b in v["bridges"] if "Filtered" in b]) == 1


def test_migrating_next_to_a_relay_bridges_directly(line):
    # Filter to Archive: its input comes straight from the robot, its output goes to the
    # cloud's Mapper; nothing passes through a container that only relays
    v = view(resolved(line, "FilterToArchive").system)
    assert v["placement"]["Filter"] == "Archive"
    assert "Robot.endpoint.sub_Scan -> Archive.endpoint.pub_Scan" in v["bridges"]
    assert "Archive.endpoint.sub_Filtered -> Cloud.endpoint.pub_Filtered" in v["bridges"]
    assert not any(b.startswith("Robot.endpoint.sub_Filtered") for b in v["bridges"])


def test_explain_names_the_migration_and_its_resolution_element(line):
    resolution = resolve(line, selection_from_list("MoveFilter"))
    text = "\n".join(str(e) for e in resolution.trace.about("Filter"))
    assert "migrated: from Robot to Cloud by 'when MoveFilter selected'" in text
    assert "migrations.rm:5:" in text
