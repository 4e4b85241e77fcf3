"""The NetworkPolicies of a bundle allow exactly the connections of the resolved
architecture (docs/kubernetes.md, "What the policies allow").

The expected connections are derived here from the model, without the policy emitter:
the crossings of the flow table as each robot's deployment places them
(:class:`spl.resolver.architecture.wiring.Wiring`), the writers and readers of the stores, and the
product's database. A crossing with a robot at one end means a robot dials the Zenoh
router (from outside the cluster); each cloud instance at an end of a crossing is
dialled by the router on its bridges' ports; a writer or reader on a robot calls its
store's service from outside, one in a cloud instance from that instance's pods; each
service of a PostgreSQL product connects to PostgreSQL. The policies are read back from
the manifests, ingress and egress apart, and must give exactly that set, in every
shipped product and in both shipped fleets; every namespace denies everything else.
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import pytest
import yaml

from spl.generators.bundle.writer import build_bundle
from spl.generators.fleet.bundle import fleet_files
from spl.generators.transport.bridge import transport
from spl.metamodels import tsm
from spl.resolver.architecture.generated_names import kubernetes_label
from spl.resolver.architecture.placement import Placement
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.stores import cloud_stores, database_kind, store_names
from spl.resolver.architecture.wiring import Wiring
from spl.resolver.fleets.deployment import deploy
from spl.resolver.fleets.fleet import check_fleet
from spl.resolver.fleets.fleet_file import load_fleet

from support.shipped_products import shipped_products

ROOT = Path(__file__).resolve().parents[2]
FLEETS = sorted((ROOT / "product_lines").glob("*/fleets/*.yaml"))
OUTSIDE = "(outside the cluster)"
NAME = "app.kubernetes.io/name"
Pair = tuple[str, str, int]  # source, target, port


def zenoh_pairs(products: list[ResolvedProduct], ports: dict[str, set[int]]) -> set[Pair]:
    """Robots to the router and the router to every cloud instance a crossing of the flow
    table reaches (``ports``: the instance's bridge ports, by object name)."""
    if not transport(*products).carried:
        return set()
    pairs: set[Pair] = set()
    for product in products:
        errors: list = []
        placement = Placement(product.system, errors)
        wiring = Wiring(product.flows, placement, errors)
        for robot in placement.robots:
            for crossing in wiring.crossings(robot):
                for place in (crossing.source, crossing.target):
                    if place.is_robot:
                        pairs.add((OUTSIDE, "zenoh-router", 7447))
                    else:
                        name = kubernetes_label(place.tag)
                        pairs |= {("zenoh-router", name, port) for port in ports[name]}
        assert not errors
    return pairs


def store_pairs(product: ResolvedProduct) -> set[Pair]:
    """Writers and readers to their stores' services; the services to PostgreSQL."""
    system = product.system
    stores = cloud_stores(system)
    names = store_names(system)
    T = tsm()
    errors: list = []
    placement = Placement(system, errors)
    pairs: set[Pair] = set()
    for container in system.containers:
        for node in container.nodes:
            if isinstance(node, T.Writer | T.Reader):
                service = names[id(node.store)].dns
                if placement.is_robot(container):
                    pairs.add((OUTSIDE, service, 8000))
                else:
                    for instance in placement.cloud_instances():
                        if any(n is node for n in instance.nodes):
                            pairs.add((kubernetes_label(instance.place.tag), service, 8000))
    if stores and database_kind(product) == "postgresql":
        pairs |= {(names[id(store)].dns, "postgres", 5432) for store in stores}
    assert not errors
    return pairs


def manifests(files: dict[str, bytes]) -> list[dict]:
    return [
        document
        for path, data in sorted(files.items())
        if path.endswith(".yaml") and "kubernetes/" in path and "kustomization" not in path
        for document in yaml.safe_load_all(data)
    ]


def allowed(documents: list[dict]) -> dict[str, tuple[set[Pair], set[Pair]]]:
    """namespace -> (pairs its ingress rules allow, pairs its egress rules allow), from
    the workload policies; the namespace-wide ones are checked to deny all but DNS."""
    found: dict[str, tuple[set[Pair], set[Pair]]] = defaultdict(lambda: (set(), set()))
    namespaces = {d["metadata"]["name"] for d in documents if d["kind"] == "Namespace"}
    for document in documents:
        if document["kind"] != "NetworkPolicy":
            continue
        namespace, spec = document["metadata"]["namespace"], document["spec"]
        incoming, outgoing = found[namespace]
        if spec["podSelector"] == {}:
            assert namespace in namespaces
            assert spec.get("ingress") is None  # nothing comes in
            for rule in spec.get("egress", []):  # and only DNS goes out
                assert {p["port"] for p in rule["ports"]} == {53}
                assert rule["to"][0]["namespaceSelector"]["matchLabels"] == {
                    "kubernetes.io/metadata.name": "kube-system"
                }
            continue
        assert spec["policyTypes"] == ["Ingress", "Egress"]
        name = spec["podSelector"]["matchLabels"][NAME]
        for rule in spec["ingress"]:
            peers = [p["podSelector"]["matchLabels"][NAME] for p in rule.get("from", [])]
            for peer in peers or [OUTSIDE]:
                incoming |= {(peer, name, p["port"]) for p in rule["ports"]}
        for rule in spec["egress"]:
            for peer in [p["podSelector"]["matchLabels"][NAME] for p in rule["to"]]:
                outgoing |= {(name, peer, p["port"]) for p in rule["ports"]}
    for namespace in namespaces:  # each namespace denies all, in and out
        deny = [
            d
            for d in documents
            if d["kind"] == "NetworkPolicy"
            and d["metadata"]["namespace"] == namespace
            and d["spec"] == {"podSelector": {}, "policyTypes": ["Ingress", "Egress"]}
        ]
        assert len(deny) == 1
    return found


def workloads(documents: list[dict]) -> dict[str, set[str]]:
    """namespace -> names of its Deployments and StatefulSets."""
    found: dict[str, set[str]] = defaultdict(set)
    for document in documents:
        if document["kind"] in ("Deployment", "StatefulSet"):
            found[document["metadata"]["namespace"]].add(document["metadata"]["name"])
    return found


def bridge_ports(documents: list[dict]) -> dict[str, set[int]]:
    """The Zenoh ports of every workload (its containers' ports named ``zenoh*``)."""
    ports: dict[str, set[int]] = defaultdict(set)
    for document in documents:
        if document["kind"] == "Deployment":
            for container in document["spec"]["template"]["spec"]["containers"]:
                for port in container.get("ports", []):
                    if port["name"].startswith("zenoh"):
                        ports[document["metadata"]["name"]].add(port["containerPort"])
    return ports


def check(expected: dict[str, set[Pair]], documents: list[dict]) -> None:
    found = allowed(documents)
    assert {n for n in expected if expected[n]} <= set(found)
    for namespace, (incoming, outgoing) in found.items():
        want = expected.get(namespace, set())
        assert incoming | outgoing == want, namespace
        # both ends of a pair inside the cluster allow it; outside ends only by ingress
        assert outgoing == {pair for pair in want if pair[0] != OUTSIDE}
        assert incoming == want
        # and every workload is selected by a policy of its own
        names = {
            d["spec"]["podSelector"].get("matchLabels", {}).get(NAME)
            for d in documents
            if d["kind"] == "NetworkPolicy" and d["metadata"]["namespace"] == namespace
        }
        assert workloads(documents)[namespace] <= names


@pytest.mark.parametrize(
    ("path", "product"), list(shipped_products()), ids=lambda value: getattr(value, "stem", "")
)
def test_every_product_allows_exactly_its_flows(path, product):
    documents = manifests(build_bundle(product).files)
    (namespace,) = {d["metadata"]["name"] for d in documents if d["kind"] == "Namespace"}
    want = zenoh_pairs([product], bridge_ports(documents)) | store_pairs(product)
    check({namespace: want}, documents)


def test_the_paper_product_allows_what_its_architecture_says():
    """Pinned by hand for one product, so the derivation above is not the only witness."""
    paper = ROOT / "product_lines" / "mapping3d" / "products" / "youbot_stereo_room.yaml"
    product = dict(shipped_products())[paper]
    found = allowed(manifests(build_bundle(product).files))
    incoming, outgoing = found["youbot-stereo-room"]
    instances = {name for _, name, _ in outgoing}
    assert (OUTSIDE, "zenoh-router", 7447) in incoming
    assert len(instances) == 2 and all(n.startswith("mappingcloud-") for n in instances)
    assert {port for _, _, port in outgoing} == {7447}


@pytest.mark.parametrize("fleet_file", FLEETS, ids=lambda p: p.stem)
def test_every_fleet_allows_exactly_its_flows(fleet_file):
    result = check_fleet(load_fleet(fleet_file))
    assert result.ok
    deployment = deploy(result)
    files = fleet_files(deployment)
    documents = manifests(files)
    products = [entry.product for entry in deployment.robots]
    fleet = [d for d in manifests({k: v for k, v in files.items() if k.startswith("kubernetes/")})]
    (namespace,) = {d["metadata"]["name"] for d in fleet if d["kind"] == "Namespace"}
    expected = {namespace: zenoh_pairs(products, bridge_ports(fleet))}
    for product in products:  # each robot's data services in its own namespace
        if cloud_stores(product.system):
            own = kubernetes_label(product.name)
            expected[own] = expected.get(own, set()) | store_pairs(product)
    check(expected, documents)
