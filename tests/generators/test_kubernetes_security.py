"""Every workload of every shipped product at the restricted Pod Security level, with
requests, limits and probes, in its product's namespace (docs/kubernetes.md); the
namespace option and the resource attributes, and what they refuse."""

from __future__ import annotations

import pytest
import yaml

from spl.core.diagnostics import ModelError
from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle
from spl.generators.deploy import generator as deploy
from spl.generators.workloads.resources import resources
from spl.generators.workloads.security import (
    UID,
    WAIVERS,
    checked_namespace,
    namespace_for,
)
from spl.resolver.architecture.product import ResolvedProduct

from support.cli_outcome import run
from support.service_models import product as data_product
from support.shipped_products import LINES, shipped_products

PAPER = LINES / "mapping3d" / "products" / "youbot_stereo_room.yaml"


def workloads(files: dict[str, bytes]) -> list[dict]:
    return [
        document
        for path, data in files.items()
        if path.endswith(".yaml") and "kubernetes/" in path
        for document in yaml.safe_load_all(data)
        if document["kind"] in ("Deployment", "StatefulSet")
    ]


def test_every_shipped_workload_is_restricted_sized_and_probed():
    seen = 0
    for _, product in shipped_products():
        files = build_bundle(product).files
        namespace = namespace_for(product.name)
        for workload in workloads(files):
            seen += 1
            assert workload["metadata"]["namespace"] == namespace
            annotations = workload["metadata"]["annotations"]
            waived = {v.partition("=")[0] for k, v in annotations.items() if "checkov" in k}
            assert waived == set(WAIVERS)
            pod = workload["spec"]["template"]["spec"]
            assert pod["automountServiceAccountToken"] is False
            assert pod["securityContext"]["runAsNonRoot"] is True
            assert pod["securityContext"]["runAsUser"] == UID >= 10000
            assert pod["securityContext"]["seccompProfile"] == {"type": "RuntimeDefault"}
            for container in pod["containers"]:
                context = container["securityContext"]
                assert context["allowPrivilegeEscalation"] is False
                assert context["readOnlyRootFilesystem"] is True
                assert context["capabilities"] == {"drop": ["ALL"]}
                assert {"name": "tmp", "mountPath": "/tmp"} in container["volumeMounts"]
                for amounts in ("requests", "limits"):
                    assert set(container["resources"][amounts]) == {"cpu", "memory"}
                assert "readinessProbe" in container and "livenessProbe" in container
                assert "valueFrom" not in str(container.get("env", []))  # secrets as files
    assert seen > 40


def test_namespace_is_the_products_name_or_the_option(tmp_path):
    assert namespace_for("youbot_stereo_room") == "youbot-stereo-room"
    long = namespace_for("A" * 80)
    assert len(long) <= 63 and checked_namespace(long) == long
    assert namespace_for("A" * 80) != namespace_for("A" * 81)  # a digest of the whole
    assert namespace_for("___").startswith("spl-")  # no label: spl- and a digest
    assert BundleOptions(namespace="prod").namespace_of("anything") == "prod"
    assert BundleOptions().namespace_of("youbot_stereo_room") == "youbot-stereo-room"
    with pytest.raises(ValueError, match="'Bad_Name' is not a DNS-1123 label"):
        checked_namespace("Bad_Name")
    with pytest.raises(ValueError, match="'Bad_Name' is not a DNS-1123 label"):
        BundleOptions(namespace="Bad_Name")  # options are checked when made, not when read
    product = dict(shipped_products())[PAPER]
    chosen = build_bundle(product, BundleOptions(namespace="robots-prod")).files
    assert {w["metadata"]["namespace"] for w in workloads(chosen)} == {"robots-prod"}
    # the option is the call's own: the next bundle is in the product's namespace again
    again = build_bundle(product).files
    assert {w["metadata"]["namespace"] for w in workloads(again)} == {"youbot-stereo-room"}
    out = tmp_path / "bundle"
    result = run(
        "resolve", LINES / "mapping3d", "--features", PAPER, "-o", out, "--namespace", "robots-prod"
    )
    assert result.exit_code == 0, result.output
    placed = {
        document["metadata"].get("namespace", document["metadata"]["name"])
        for path in (out / "kubernetes").glob("*.yaml")
        if path.name != "kustomization.yaml"
        for document in yaml.safe_load_all(path.read_text())
    }
    assert placed == {"robots-prod"}
    refused = run(
        "resolve",
        LINES / "mapping3d",
        "--features",
        PAPER,
        "-o",
        tmp_path / "x",
        "--namespace",
        "-x",
    )
    assert refused.exit_code == 2 and "is not a DNS-1123 label" in refused.stderr
    assert not (tmp_path / "x").exists()


def with_attributes(**attributes: object) -> ResolvedProduct:
    resolved = data_product()
    values = {f"Storage.{name}": value for name, value in attributes.items()}
    return ResolvedProduct(
        resolved.name, resolved.system, resolved.features, {**resolved.attributes, **values}
    )


def test_resources_come_from_the_model_else_the_defaults():
    assert resources("service") == {
        "requests": {"cpu": "100m", "memory": "128Mi"},
        "limits": {"cpu": "1", "memory": "512Mi"},
    }
    sized = with_attributes(service_cpu=0.5, service_memory=768)
    assert resources("service", sized) == {
        "requests": {"cpu": "500m", "memory": "768Mi"},
        "limits": {"cpu": "500m", "memory": "768Mi"},
    }
    assert resources("postgres", sized) == resources("postgres")  # another kind's
    # a TSM container's cpu and memory win over the attributes
    assert resources("ros", with_attributes(ros_cpu=1), cpu=4, memory=4096)["limits"] == {
        "cpu": "4",
        "memory": "4096Mi",
    }
    for bad in ({"service_cpu": "lots"}, {"service_cpu": -1}, {"service_memory": 1.5}):
        with pytest.raises(ModelError, match=f"attribute Storage.{next(iter(bad))}"):
            resources("service", with_attributes(**bad))
    deployed = deploy.generate(with_attributes(service_memory=768))
    (service,) = [w for w in workloads(deployed) if w["metadata"]["name"] == "follow-store"]
    assert service["spec"]["template"]["spec"]["containers"][0]["resources"]["limits"] == {
        "cpu": "1",
        "memory": "768Mi",
    }


def test_a_fleet_is_in_its_namespace_and_each_robots_services_in_their_own(tmp_path):
    field = LINES / "data_acquisition" / "fleets" / "field.yaml"

    def namespaces(out):  # type: ignore[no-untyped-def]
        files = {
            str(p.relative_to(out)): p.read_bytes()
            for p in out.rglob("*.yaml")
            if "kubernetes" in p.parts and p.name != "kustomization.yaml"
        }
        made = sorted(p for p in files if p.endswith("namespace.yaml"))
        placed = {
            path.split("/deploy/")[0]: document["metadata"]["namespace"]
            for path, data in files.items()
            for document in yaml.safe_load_all(data)
            if document["kind"] != "Namespace"
        }
        return made, placed

    assert run("fleet", "resolve", field, "-o", tmp_path / "a").exit_code == 0
    made, placed = namespaces(tmp_path / "a")
    assert made == [
        "kubernetes/namespace.yaml",
        *(
            f"robots/{r}/deploy/kubernetes/namespace.yaml"
            for r in ("ev3_pair", "rover_1", "rover_2")
        ),
    ]
    assert {v for k, v in placed.items() if k.startswith("kubernetes/")} == {"field"}
    for robot in ("ev3_pair", "rover_1", "rover_2"):  # each robot's product's own
        assert placed[f"robots/{robot}"] != "field"
    assert len({placed[f"robots/{r}"] for r in ("ev3_pair", "rover_1", "rover_2")}) == 3
    given = run("fleet", "resolve", field, "-o", tmp_path / "b", "--namespace", "one")
    assert given.exit_code == 0, given.output
    made, placed = namespaces(tmp_path / "b")
    assert made == ["kubernetes/namespace.yaml"] and set(placed.values()) == {"one"}
