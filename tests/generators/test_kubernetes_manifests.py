"""Kubernetes manifests of chosen products: the instances the placement rule gives (the
Rapyuta files' containers), their objects, names refused with located errors, the
``--target`` option and determinism."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from spl.core.diagnostics import ModelError
from spl.dsl.tsm import language as tsm_language
from spl.generators.bundle.writer import TARGETS, build_bundle
from spl.generators.kubernetes import manifests as kubernetes
from spl.generators.rapyuta import configurations as rapyuta
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.cli_outcome import LOCATED_ERROR, run

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"
TWO_ROBOTS = Path(__file__).parents[1] / "models" / "rapyuta" / "two_robots.tsm"
PAPER = "YouBot,Stereo,AdditionalPC,Room"


def objects(files: dict[str, bytes]) -> dict[tuple[str, str], dict]:
    """(kind, name) -> object, over every manifest of the folder."""
    found = {}
    for path, data in files.items():
        if path.endswith(".yaml") and path != "kubernetes/kustomization.yaml":
            for document in yaml.safe_load_all(data):
                found[(document["kind"], document["metadata"]["name"])] = document
    return found


def two_robots() -> ResolvedProduct:
    return ResolvedProduct("two", tsm_language.parse_file(TWO_ROBOTS), ())


def test_two_robots_give_two_private_instances_one_protected_one_public():
    product = two_robots()
    files = kubernetes.generate(product)
    deployments = {
        name: d
        for (kind, name), d in objects(files).items()
        if kind == "Deployment" and name != "zenoh-router"
    }
    assert ("Deployment", "zenoh-router") in objects(files)  # the robots' way in
    instances = {
        "mappingcloud-alpha": ("MappingCloud_alpha", "private", "VisualOdometry, MapOptimizer"),
        "mappingcloud-beta": ("MappingCloud_beta", "private", "VisualOdometry, MapOptimizer"),
        "mappingcloud-mappers": ("MappingCloud_mappers", "protected", "Database, StrategyPlanner"),
        "mappingcloud-public": ("MappingCloud_public", "public", "MapMerger"),
    }
    assert set(deployments) == set(instances)
    for name, (tag, mode, nodes) in instances.items():
        metadata = deployments[name]["metadata"]
        assert metadata["labels"]["spl.robotics/placement"] == tag
        assert metadata["labels"]["spl.robotics/sharing"] == mode
        assert metadata["labels"]["spl.robotics/container"] == "MappingCloud"
        assert metadata["labels"]["app.kubernetes.io/part-of"] == "two"
        assert metadata["annotations"]["spl.robotics/nodes"] == nodes
    robots = {
        n: d["metadata"]["annotations"]["spl.robotics/robots"] for n, d in deployments.items()
    }
    assert robots["mappingcloud-mappers"] == robots["mappingcloud-public"] == "alpha, beta"
    assert robots["mappingcloud-alpha"] == "alpha"
    # the same instances as the containers the Rapyuta files declare
    declared = {
        container["cTag"]
        for data in rapyuta.generate(product).values()
        for container in json.loads(data)["containers"]
    }
    assert declared == {tag for tag, _, _ in instances.values()}
    # each instance launches exactly its nodes, with the container's resources
    config = objects(files)[("ConfigMap", "mappingcloud-mappers-config")]
    launch = config["data"]["launch.xml"]
    assert launch.count("<node ") == 2 and 'name="Database"' in launch
    assert 'name="StrategyPlanner"' in launch and "MapMerger" not in launch
    ros = deployments["mappingcloud-alpha"]["spec"]["template"]["spec"]["containers"][0]
    assert ros["args"] == ["ros2", "launch", "/etc/spl/launch.xml"]
    assert ros["resources"] == {
        "requests": {"cpu": "4", "memory": "4096Mi"},
        "limits": {"cpu": "4", "memory": "4096Mi"},
    }
    # ready when the ROS 2 graph holds every node the instance launches
    probe = deployments["mappingcloud-mappers"]["spec"]["template"]["spec"]["containers"][0]
    script = probe["readinessProbe"]["exec"]["command"][-1]
    assert "ros2 node list" in script and "/Database" in script and "/StrategyPlanner" in script


def test_paper_product_bridges_each_instance_and_reads_passwords_from_a_secret():
    line = load_product_line(MAPPING)
    files = kubernetes.generate(resolve(line, selection_from_list(PAPER)).product)
    assert sorted(files) == [
        "kubernetes/README.md",
        "kubernetes/kustomization.yaml",
        "kubernetes/mappingcloud-mappers.yaml",
        "kubernetes/mappingcloud-robot-1.yaml",
        "kubernetes/namespace.yaml",
        "kubernetes/zenoh-router.yaml",
    ]
    found = objects(files)
    for name in ("mappingcloud-mappers", "mappingcloud-robot-1"):
        pod = found[("Deployment", name)]["spec"]["template"]["spec"]
        assert [c["name"] for c in pod["containers"]] == ["ros", "zenoh-bridge"]
        service = found[("Service", name)]["spec"]
        assert service["selector"] == {"app.kubernetes.io/name": name}
        assert service["ports"][0]["port"] == 7447
        # only the router reaches the bridge, on its port; the pod dials nobody
        policy = found[("NetworkPolicy", name)]["spec"]
        assert policy["ingress"] == [
            {
                "from": [
                    {"podSelector": {"matchLabels": {"app.kubernetes.io/name": "zenoh-router"}}}
                ],
                "ports": [{"protocol": "TCP", "port": 7447}],
            }
        ]
        assert policy["egress"] == []
    pod = found[("Deployment", "zenoh-router")]["spec"]["template"]["spec"]
    router = pod["containers"][0]
    # the password is a read-only file of the Secret, never an environment variable
    assert "env" not in router
    assert {"name": "credentials", "mountPath": "/run/secrets/zenoh-router", "readOnly": True} in (
        router["volumeMounts"]
    )
    assert {
        "name": "credentials",
        "secret": {"secretName": "zenoh-router-credentials", "defaultMode": 0o440},
    } in pod["volumes"]
    assert "$(cat /run/secrets/zenoh-router/rce-password)" in router["command"][2]
    (namespace,) = [o for (kind, _), o in found.items() if kind == "Namespace"]
    assert namespace["metadata"]["labels"]["pod-security.kubernetes.io/enforce"] == "restricted"
    assert {o["metadata"]["namespace"] for o in found.values() if o is not namespace} == {
        namespace["metadata"]["name"]
    }
    assert {key[0] for key in found} == {
        "Namespace", "NetworkPolicy", "ConfigMap", "Deployment", "Service",
    }  # fmt: skip
    assert found[("Service", "zenoh-router")]["spec"]["type"] == "LoadBalancer"
    readme = files["kubernetes/README.md"].decode()
    assert "kubectl apply -k kubernetes/" in readme
    assert "--from-literal=rce-password=" in readme


def test_same_product_same_bytes():
    line = load_product_line(MAPPING)
    first = build_bundle(resolve(line, selection_from_list(PAPER)).product).files
    second = build_bundle(resolve(line, selection_from_list(PAPER)).product).files
    chosen = [p for p in first if p.startswith(("kubernetes/", "zenoh/"))]
    assert len(chosen) >= 10
    assert {p: first[p] for p in chosen} == {p: second[p] for p in chosen}


def clashing_line(folder: Path, first: str, second: str) -> Path:
    """A line whose two robots' ids give one Kubernetes name to their private instances."""
    text = TWO_ROBOTS.read_text()
    text = text.replace('robot_id "alpha"', f'robot_id "{first}"')
    text = text.replace('robot_id "beta"', f'robot_id "{second}"')
    (folder / "two.tsm").write_text(text)
    (folder / "two.fm").write_text("feature model Two\nroot Two { }\n")
    (folder / "two.rm").write_text('resolution model Two\ntsm "two.tsm"\nfm "two.fm"\n')
    return folder


@pytest.mark.parametrize(
    ("first", "second", "message"),
    [
        ("Alpha_1", "alpha-1", "both give the Kubernetes name 'mappingcloud-alpha-1'"),
        ("a" * 60, "beta", "longer than 56 characters"),
    ],
)
def test_names_that_cannot_map_are_located_errors_and_nothing_is_written(
    tmp_path, first, second, message
):
    line = clashing_line(tmp_path, first, second)
    with pytest.raises(ModelError) as raised:
        kubernetes.generate(ResolvedProduct("two", tsm_language.parse_file(line / "two.tsm"), ()))
    assert any(message in d.message and d.location is not None for d in raised.value.diagnostics)
    out = tmp_path / "out"
    out.mkdir()
    result = run("resolve", line, "--features", "Two", "-o", out / "bundle")
    assert result.exit_code == 1, result.output
    assert LOCATED_ERROR.search(result.stderr) and message in result.stderr
    assert "two.tsm:" in result.stderr and "Traceback" not in result.stderr
    assert list(out.iterdir()) == []
    # the other targets still resolve this model
    assert (
        run("resolve", line, "--features", "Two", "-o", out / "b", "--target", "ros2").exit_code
        == 0
    )


def test_target_option_writes_only_the_chosen_outputs(tmp_path):
    out = tmp_path / "bundle"
    result = run("resolve", MAPPING, "--features", PAPER, "-o", out, "--target", "zenoh,kubernetes")
    assert result.exit_code == 0, result.output
    written = sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file())
    assert {p.split("/")[0] for p in written} == {
        "kubernetes",
        "zenoh",
        "manifest.json",
        "resolved.tsm",
        "resolved.xmi",
    }
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["targets"] == ["kubernetes", "zenoh"]
    everything = tmp_path / "all"
    assert run("resolve", MAPPING, "--features", PAPER, "-o", everything).exit_code == 0
    assert json.loads((everything / "manifest.json").read_text())["targets"] == list(TARGETS)
    refused = run("resolve", MAPPING, "--features", PAPER, "-o", tmp_path / "x", "--target", "k8s")
    assert refused.exit_code == 2
    assert "unknown target k8s; targets: ros1, ros2, rapyuta" in refused.stderr
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize(
    ("mode", "instances"),
    [
        ("public", {"MappingCloud_public": "public", "MappingCloud_robot_1": "private"}),
        ("private", {"MappingCloud_robot_1": "private"}),
    ],
)
def test_sharing_override_moves_the_shared_nodes(mode, instances):
    line = load_product_line(MAPPING)
    selection = selection_from_list(PAPER)
    selection.sharing = {"SharedMap": mode}
    files = kubernetes.generate(resolve(line, selection).product)
    deployments = [d for (kind, _), d in objects(files).items() if kind == "Deployment"]
    found = {
        d["metadata"]["labels"]["spl.robotics/placement"]: d["metadata"]["labels"][
            "spl.robotics/sharing"
        ]
        for d in deployments
        if d["metadata"]["name"] != "zenoh-router"
    }
    assert found == instances
    database = [
        d["metadata"]["labels"]["spl.robotics/placement"]
        for d in deployments
        if "Database" in d["metadata"].get("annotations", {}).get("spl.robotics/nodes", "")
    ]
    assert database == [f"MappingCloud_{'public' if mode == 'public' else 'robot_1'}"]
