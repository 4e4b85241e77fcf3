"""``spl fleet resolve`` writes Kubernetes manifests for the fleet: one Deployment per
shared instance (per protected group, one public), not per robot, and one per robot's
private instance; every manifest passes ``kubernetes-validate --strict``. The Zenoh
bridges are computed over the whole fleet: each robot under its own namespace, a
shared instance with one bridge per robot it serves."""

from __future__ import annotations

import json
from pathlib import Path

import json5
import kubernetes_validate
import yaml

from support.cli_outcome import run

ROOT = Path(__file__).resolve().parents[2]
LAB = ROOT / "product_lines" / "mapping3d" / "fleets" / "lab.yaml"


def test_fleet_deploys_each_shared_instance_once(tmp_path):
    out = tmp_path / "lab"
    result = run("fleet", "resolve", LAB, "-o", out)
    assert result.exit_code == 0, result.output
    folder = out / "kubernetes"
    deployments = {}
    for path in sorted(folder.glob("*.yaml")):
        if path.name == "kustomization.yaml":
            continue
        for document in yaml.safe_load_all(path.read_text()):
            kubernetes_validate.validate(document, "1.33.0", strict=True)
            if document["kind"] == "Deployment" and path.name != "zenoh-router.yaml":
                labels = document["metadata"]["labels"]
                deployments[labels["spl.robotics/placement"]] = (
                    labels["spl.robotics/sharing"],
                    document["metadata"]["annotations"]["spl.robotics/robots"],
                    labels["app.kubernetes.io/part-of"],
                )
    # lab.yaml: youbot_1, youbot_2 share the lab's protected instance; roomba_1 and
    # roomba_2 (robotID roomba-cellar) share the public one; youbot_3 keeps its map private
    assert deployments == {
        "MappingCloud_lab": ("protected", "youbot_1, youbot_2", "lab"),
        "MappingCloud_public": ("public", "roomba_1, roomba_2", "lab"),
        "MappingCloud_youbot_1": ("private", "youbot_1", "lab"),
        "MappingCloud_youbot_2": ("private", "youbot_2", "lab"),
        "MappingCloud_youbot_3": ("private", "youbot_3", "lab"),
        "MappingCloud_roomba_1": ("private", "roomba_1", "lab"),
        "MappingCloud_roomba-cellar": ("private", "roomba-cellar", "lab"),
    }
    kustomization = yaml.safe_load((folder / "kustomization.yaml").read_text())
    assert kustomization["resources"] == sorted(
        p.name for p in folder.glob("*.yaml") if p.name != "kustomization.yaml"
    )
    # the shared nodes are launched by the shared instances only
    shared = (folder / "mappingcloud-lab.yaml").read_text()
    assert 'name="StrategyPlanner"' in shared
    assert "StrategyPlanner" not in (folder / "mappingcloud-youbot-1.yaml").read_text()
    assert "StrategyPlanner" in (folder / "mappingcloud-youbot-3.yaml").read_text()
    # robots carry no deployment of their own; the fleet manifest lists the files
    assert not (out / "robots" / "youbot_1" / "kubernetes").exists()
    assert not (out / "robots" / "youbot_1" / "zenoh").exists()
    fleet = json.loads((out / "fleet.json").read_text())
    assert "kubernetes/mappingcloud-lab.yaml" in fleet["shared"]["MappingCloud_lab"]["files"]
    assert "kubernetes/mappingcloud-youbot-1.yaml" in fleet["robots"]["youbot_1"]["files"]
    assert "kubernetes/kustomization.yaml" in fleet["files"]


def test_fleet_bridges_give_each_robot_its_namespace(tmp_path):
    out = tmp_path / "lab"
    assert run("fleet", "resolve", LAB, "-o", out).exit_code == 0
    configs = {
        path.name.removesuffix(".json5"): json5.loads(path.read_text())
        for path in (out / "zenoh").glob("*.json5")
    }

    def namespace(name):
        return configs[name].get("plugins", {}).get("ros2dds", {}).get("namespace")

    robots = ["youbot_1", "youbot_2", "youbot_3", "roomba_1", "roomba-cellar"]
    assert [namespace(r) for r in robots] == [
        "/youbot_1",
        "/youbot_2",
        "/youbot_3",
        "/roomba_1",
        "/roomba_cellar",
    ]
    # the lab's protected instance serves youbot_1 and youbot_2, each through its bridge
    assert {namespace("MappingCloud_lab"), namespace("MappingCloud_lab.2")} == {
        "/youbot_1",
        "/youbot_2",
    }
    assert "MappingCloud_lab.3" not in configs  # youbot_3 keeps its map private
    lab = configs["MappingCloud_lab"]["plugins"]["ros2dds"]["allow"]
    assert lab["service_servers"] == [
        "/exploration/next_target",
        "/mapping/db/add_keyframe",
        "/mapping/db/update_poses",
    ]
    router = configs["zenoh-router"]["connect"]["endpoints"]
    assert "tcp/mappingcloud-lab:7448" in router and "tcp/mappingcloud-public:7448" in router
