"""A robot gets a private instance only where it can feed it or be fed by it
(docs/deployment.md, "Private instances"), on the wind-farm test line
(tests/models/windfarm: a blade crawler and a drone, a vessel edge cloud and an onshore
cloud). The crawler alone feeds the DefectDetector and the ThicknessAnalyzer (and,
through its own detector, the DefectTrend); the drone alone feeds the FlightPlanner and
reads the timer-driven WeatherFeed. Every deployment target (Rapyuta, Kubernetes, Zenoh,
the fleet's bundle) follows the one decision; ``spl explain`` says why."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from spl.cli import main
from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle, write_bundle
from spl.generators.fleet.bundle import fleet_files
from spl.resolver.architecture.placement import Placement
from spl.resolver.fleets.deployment import deploy
from spl.resolver.fleets.fleet import check_fleet
from spl.resolver.fleets.fleet_file import load_fleet
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file, selection_from_list
from spl.smoke.planning import load_plan

from support.instance_chains import (
    kubernetes_instances,
    launch_instances,
    rapyuta_instances,
    zenoh_places,
)

WINDFARM = Path(__file__).resolve().parents[2] / "tests" / "models" / "windfarm"
FULL = WINDFARM / "products" / "full.yaml"

# what each robot gets in the product with the defect trend (products/full.yaml)
CRAWLER = {
    "VesselEdge_crawler_1": {"DefectDetector"},
    "Onshore_crawler_1": {"ThicknessAnalyzer", "DefectTrend"},
}
DRONE = {"VesselEdge_drone_1": {"FlightPlanner", "WeatherFeed"}}
PRIVATE = {"VesselEdge_crawler_1", "Onshore_crawler_1", "VesselEdge_drone_1", "Onshore_drone_1"}


@pytest.fixture(scope="module")
def product():
    return resolve(load_product_line(WINDFARM), load_selection_file(FULL)).product


@pytest.fixture(scope="module")
def bundle(product):
    return build_bundle(product, BundleOptions(render_diagrams=False))


def test_the_placement_gives_each_robot_the_instances_it_feeds_or_reads(product):
    placement = Placement(product.system, [], flows=product.flows)
    instances = {i.place.tag: {n.name for n in i.nodes} for i in placement.cloud_instances()}
    assert instances == {
        **CRAWLER,
        **DRONE,
        "VesselEdge_public": {"PhotoArchive"},
        "Onshore_public": {"ReportArchive"},
    }
    # the drone uses Onshore (through the vessel) but gets no instance of it
    drone = next(r for r in placement.robots if r.name == "Drone")
    assert {c.name for c in placement.scope(drone)} == {"VesselEdge", "Onshore"}
    assert [i.place.tag for i in placement.partitions(drone)] == [
        "Onshore_public",
        "VesselEdge_drone_1",
        "VesselEdge_public",
    ]


def test_kubernetes_deploys_no_instance_the_drone_cannot_feed(bundle):
    files = bundle.files
    assert kubernetes_instances(files) == {**CRAWLER, **DRONE}
    assert "kubernetes/onshore-drone-1.yaml" not in files
    kustomization = files["kubernetes/kustomization.yaml"].decode()
    assert "onshore-drone-1" not in kustomization
    # no NetworkPolicy, Service or README names the absent instance
    assert not [
        p for p, d in files.items() if p.startswith("kubernetes/") and b"onshore-drone-1" in d
    ]
    assert "Onshore_drone_1" not in files["kubernetes/README.md"].decode()
    drone_instance = files["kubernetes/vesseledge-drone-1.yaml"].decode()
    assert "DefectDetector" not in drone_instance and "/crawler/camera/image" not in drone_instance


def test_zenoh_bridges_no_instance_the_drone_cannot_feed(bundle):
    places = zenoh_places(bundle.files)
    assert "Onshore_drone_1" not in places
    assert places & PRIVATE == {"VesselEdge_crawler_1", "Onshore_crawler_1", "VesselEdge_drone_1"}
    drone_bridge = bundle.files["zenoh/VesselEdge_drone_1.json5"].decode()
    assert "/crawler/camera/image" not in drone_bridge and "/drone/pose" in drone_bridge


def test_rapyuta_declares_no_instance_the_drone_cannot_feed(bundle):
    assert rapyuta_instances(bundle.files, PRIVATE) == {**CRAWLER, **DRONE}
    drone = json.loads(bundle.files["rapyuta/Drone.json"])
    assert [c["cTag"] for c in drone["containers"]] == ["VesselEdge_drone_1"]
    tags = {i["eTag"] for i in drone["interfaces"]} | {
        c[k].split("/")[0] for c in drone["connections"] for k in ("tagA", "tagB")
    }
    assert "Onshore_drone_1" not in tags


def test_the_smoke_plan_feeds_the_detector_from_the_crawler_alone(bundle, tmp_path):
    # the rehearsal starts each container's ROS graph once (docs/smoke.md), not an
    # instance per robot: it has no drone instance to leave out, and expects only the
    # crawler's images at the detector
    write_bundle(bundle.files, tmp_path / "bundle")
    plan = load_plan(tmp_path / "bundle")
    assert {c.name for c in plan.containers} == {"Crawler", "Drone", "VesselEdge", "Onshore"}
    by_id = {i.id: i for i in plan.interfaces()}
    assert by_id["VesselEdge.DefectDetector.image"].sources == ("Crawler.BladeCamera.image",)
    assert by_id["Onshore.ThicknessAnalyzer.thickness"].sources == (
        "Crawler.UltrasonicGauge.thickness",
    )


def test_the_fleet_gives_each_team_robot_only_its_own_instances():
    check = check_fleet(load_fleet(WINDFARM / "fleets" / "teams.yaml"))
    assert check.ok, check.diagnostics
    files = fleet_files(deploy(check))
    private = {f"{c}_{team}_{robot}" for c in ("VesselEdge", "Onshore")
               for team in ("team_a", "team_b") for robot in ("Crawler", "Drone")}  # fmt: skip
    expected = {
        f"{tag.replace('crawler_1', f'{team}_Crawler').replace('drone_1', f'{team}_Drone')}": nodes
        for team in ("team_a", "team_b")
        for tag, nodes in {**CRAWLER, **DRONE}.items()
    }
    expected["Onshore_team_b_Crawler"] = {"ThicknessAnalyzer"}  # team_b has no trend
    assert kubernetes_instances(files) == expected
    assert rapyuta_instances(files, private) == expected
    launched = {}
    for team in ("team_a", "team_b"):
        launched |= launch_instances(files, f"robots/{team}/", private)
    assert launched == expected
    assert "kubernetes/onshore-team-a-drone.yaml" not in files
    assert not zenoh_places(files) & (private - set(expected))
    fleet = json.loads(files["fleet.json"])
    assert not [f for f in fleet["robots"]["team_a"]["files"] if "onshore-team-a-drone" in f]


def test_a_product_without_the_trend_still_leaves_the_drone_out():
    product = resolve(load_product_line(WINDFARM), selection_from_list("Inspection")).product
    placement = Placement(product.system, [], flows=product.flows)
    assert {i.place.tag for i in placement.cloud_instances() if i.place.kind == "private"} == {
        "VesselEdge_crawler_1",
        "Onshore_crawler_1",
        "VesselEdge_drone_1",
    }


# -- spl explain -------------------------------------------------------------------------
def explain(*args: str) -> tuple[int, list[str]]:
    result = CliRunner().invoke(main, ["explain", str(WINDFARM), "--features", str(FULL), *args])
    return result.exit_code, result.output.splitlines()


def test_explain_names_the_chain_that_keeps_an_instance_and_why_one_is_absent():
    code, lines = explain("DefectTrend")
    assert code == 0
    assert lines[-3:] == [
        "  deployed private: one per robot that feeds it or that it feeds",
        "  instance Onshore_crawler_1 for robot crawler_1: crawler_1 feeds it: "
        "crawler_1.BladeCamera.image -> VesselEdge_crawler_1.DefectDetector.image; "
        "VesselEdge_crawler_1.DefectDetector.defects -> Onshore_crawler_1.DefectTrend.defects",
        "  no instance for robot drone_1 (not run in Onshore_drone_1): nothing feeds it in "
        "drone_1's deployment (fed only by VesselEdge_drone_1.DefectDetector.defects, which "
        "nothing feeds there), so it has nothing to send either",
    ]


def test_explain_for_one_robot_says_a_source_feeds_it():
    code, lines = explain("WeatherFeed", "--robot", "drone_1")
    assert code == 0
    assert lines[-1] == (
        "  instance VesselEdge_drone_1 for robot drone_1: it feeds drone_1: "
        "VesselEdge_drone_1.WeatherFeed.wind -> drone_1.Autopilot.wind"
    )
    code, lines = explain("WeatherFeed", "--robot", "crawler_1")
    assert lines[-1] == (
        "  no instance for robot crawler_1 (not run in VesselEdge_crawler_1): no flow chain "
        "joins it with crawler_1's nodes: nothing of crawler_1 reaches it and nothing it "
        "sends reaches crawler_1"
    )


def test_explain_an_instance_by_its_tag_deployed_or_not():
    code, lines = explain("Onshore_drone_1")
    assert code == 0
    assert lines[0] == "Onshore_drone_1: not deployed: robot drone_1 gets none of its private nodes"
    assert [line.split(":")[0] for line in lines[1:]] == ["  ThicknessAnalyzer", "  DefectTrend"]
    assert (
        "fed only by crawler_1.UltrasonicGauge.thickness of another robot, whose data" in lines[1]
    )
    code, lines = explain("VesselEdge_drone_1")
    assert lines[0] == (
        "VesselEdge_drone_1: private instance of cloud container VesselEdge for robot "
        "drone_1: runs FlightPlanner, WeatherFeed"
    )
    assert lines[1].startswith("  DefectDetector: no instance for robot drone_1")
    assert explain("VesselEdge_public")[1] == [
        "VesselEdge_public: public instance of cloud container VesselEdge for robots "
        "crawler_1, drone_1: runs PhotoArchive"
    ]


def test_explain_refuses_an_unknown_robot_with_the_products_robots():
    code, lines = explain("DefectDetector", "--robot", "drone_9")
    assert code == 2
    assert lines[-1] == (
        "Error: Invalid value for --robot: no robot 'drone_9' in this product "
        "(its robots: crawler_1, drone_1)"
    )


def test_the_explain_transcripts_of_the_manual_are_what_spl_prints(monkeypatch):
    root = WINDFARM.parents[2]
    page = (root / "docs" / "commands.md").read_text(encoding="utf-8")
    section = page.split("## spl explain", 1)[1].split("\n## ", 1)[0]
    transcripts = [
        block for block in section.split("```text\n")[1:] if "product_lines/orchard" in block
    ]
    assert transcripts, "the manual shows a private node's instances"
    monkeypatch.chdir(root)
    for block in transcripts:
        for command in block.split("```", 1)[0].split("$ spl ")[1:]:
            line, *shown = command.rstrip("\n").split("\n")
            result = CliRunner().invoke(main, line.split())
            assert result.exit_code == 0, result.output
            assert result.output.splitlines() == shown, line
