"""Every product of every shipped line: its whole bundle is generated, every Kubernetes
manifest passes ``kubernetes-validate --strict`` (the validator's bundled schemas, no
cluster), the kustomization lists exactly the manifests, the launch file each instance
mounts passes the ROS 2 launch XSD, no generated file holds a credential value, and no
private instance is one nothing can feed (the check of
tests/resolver/test_private_instances_shipped.py, on every product)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import kubernetes_validate
import pytest
import yaml

from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle
from spl.generators.kubernetes import objects as kubernetes_objects
from spl.generators.launch.launch_schema import validate_ros2_launch
from spl.resolver.analysis.formula import enumerate_products
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import ProductSelection

from support.instance_chains import check_product_instances

ROOT = Path(__file__).resolve().parents[2]
# PyYAML's own representer (not kubernetes_objects._DocumentNodes) on libyaml's emitter
PYYAML_NODES = kubernetes_objects._dumper(yaml.CSafeDumper, nodes=False)
LINES = sorted(p for p in (ROOT / "product_lines").iterdir() if p.is_dir())
KUBERNETES_VERSION = "1.33.0"  # a current release, well inside the validator's schemas
DNS_LABEL = re.compile(r"[a-z]([-a-z0-9]{0,61}[a-z0-9])?")


def password_variables(line) -> list[str]:
    return sorted(
        {
            c.endpoint.passwordEnv
            for c in line.tsm.containers
            if getattr(c, "endpoint", None) is not None and c.endpoint.passwordEnv
        }
    )


def manifests(files: dict[str, bytes], read: dict[bytes, list[dict]]) -> dict[str, list[dict]]:
    """The documents of every manifest; a file's documents are a function of its bytes,
    and the products of a line share most files (pharmacy's 160 products: 26 distinct
    files), so each distinct content is read once, into ``read``."""
    found = {}
    for path, data in files.items():
        if not path.startswith("kubernetes/") or not path.endswith(".yaml"):
            continue
        if path != "kubernetes/kustomization.yaml":
            if data not in read:  # libyaml's safe loader
                read[data] = list(yaml.load_all(data, Loader=yaml.CSafeLoader))
            found[path] = read[data]
    return found


def check_manifests(files: dict[str, bytes], validated: set[str], read: dict[bytes, list]) -> int:
    """Validate every object; return how many there were. The products of a line share
    most of their objects (pharmacy's 160: about one object in sixteen differs), and a
    validator's verdict is a function of the object alone: each distinct one, by its
    canonical JSON in ``validated``, is validated once."""
    count = 0
    found = manifests(files, read)
    kustomization = yaml.safe_load(files["kubernetes/kustomization.yaml"])
    assert kustomization["kind"] == "Kustomization"
    assert kustomization["resources"] == sorted(p.removeprefix("kubernetes/") for p in found)
    for path, documents in found.items():
        for document in documents:
            count += 1
            canonical = json.dumps(document, sort_keys=True)
            if canonical in validated:
                continue
            validated.add(canonical)
            kubernetes_validate.validate(document, KUBERNETES_VERSION, strict=True)
            assert DNS_LABEL.fullmatch(document["metadata"]["name"]), path
            if document["kind"] == "ConfigMap" and "launch.xml" in document["data"]:
                launch = document["data"]["launch.xml"].encode()
                assert validate_ros2_launch(launch) == [], path
    return count


@pytest.mark.parametrize("directory", LINES, ids=lambda p: p.name)
def test_every_product_validates_and_holds_no_credential(directory, monkeypatch):
    line = load_product_line(directory)
    secrets = {}
    for variable in password_variables(line):
        secrets[variable] = f"s3cret-{variable.lower()}-value"
        monkeypatch.setenv(variable, secrets[variable])
    assert secrets or directory.name == "data_acquisition"
    products = objects = 0
    validated: set[str] = set()
    read: dict[bytes, list] = {}
    written: set[tuple[tuple[str, bytes], ...]] = set()
    for features in enumerate_products(line.fm):
        product = resolve(line, ProductSelection("p", sorted(features))).product
        files = build_bundle(product, BundleOptions(render_diagrams=False)).files
        objects += check_manifests(files, validated, read)
        manifests = {p: d for p, d in files.items() if p.startswith("kubernetes/")}
        # written by PyYAML (libyaml's emitter, the pure-Python one, and PyYAML's own
        # representer) instead of kubernetes_yaml: the very same bytes. What a writer
        # writes is a function of the documents alone, which the bytes written say in
        # full: manifests already compared (pharmacy's 160 products have 32 distinct
        # sets) are not written thrice more.
        key = tuple(sorted(manifests.items()))
        if key not in written:
            written.add(key)
            for dumper in (
                kubernetes_objects.DUMPER,
                kubernetes_objects.PYTHON_DUMPER,
                PYYAML_NODES,
            ):
                with monkeypatch.context() as patch:
                    patch.setattr(kubernetes_objects, "WRITER", None)
                    patch.setattr(kubernetes_objects, "DUMPER", dumper)
                    other = build_bundle(product, BundleOptions(targets=("kubernetes",))).files
                kubernetes = {p: d for p, d in other.items() if p.startswith("kubernetes/")}
                assert manifests == kubernetes
        for path, data in files.items():
            for variable, value in secrets.items():
                assert value.encode() not in data, f"{path} holds the value of ${variable}"
        # and no private instance nothing can feed (docs/deployment.md, "Private instances")
        check_product_instances(product, files)
        products += 1
    assert products >= 8
    assert objects >= products or directory.name == "data_acquisition"
