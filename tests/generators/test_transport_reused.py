"""A bundle's Zenoh and Kubernetes generators share one computation of the product's
transport: one ``BundleInputs`` (made by the call that builds the bundle) gives the same
Transport each time it is read, another product's inputs their own; outside, each call
computes anew, and a new bundle's inputs compute it again. A fleet bundle's
``FleetInputs`` does the same for the fleet's transport."""

from __future__ import annotations

import json
from pathlib import Path

from spl.generators.bundle import writer as bundle_module
from spl.generators.bundle.inputs import BundleInputs, FleetInputs
from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle
from spl.generators.fleet.bundle import build_fleet_bundle
from spl.generators.transport.bridge import transport
from spl.resolver.fleets.deployment import deploy
from spl.resolver.fleets.fleet import check_fleet
from spl.resolver.fleets.fleet_file import load_fleet
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file

LINES = Path(__file__).resolve().parents[2] / "product_lines"
QUICK = BundleOptions(render_diagrams=False)


def products():
    line = load_product_line(LINES / "mapping3d")
    paths = sorted((LINES / "mapping3d" / "products").glob("*.yaml"))[:2]
    return [resolve(line, load_selection_file(path)).product for path in paths]


def test_one_transport_per_system_within_and_a_new_one_outside():
    first, second = products()
    outside = transport(first)
    assert transport(first) is not outside
    inputs = BundleInputs(first, QUICK)
    shared = inputs.transport
    assert inputs.transport is shared
    others = BundleInputs(second, QUICK)
    other = others.transport
    assert other is not shared
    assert others.transport is other
    assert BundleInputs(first, QUICK).transport is not shared  # a new bundle's own
    assert transport(first) is not shared
    assert shared == outside  # the same result, computed once


def test_kubernetes_and_zenoh_are_given_the_same_transport():
    """What build_bundle hands the two generators is one object, the inputs' own."""
    first, _ = products()
    inputs = BundleInputs(first, BundleOptions(namespace="lab"))
    kubernetes = bundle_module.READS["spl.generators.kubernetes.manifests"](inputs)
    zenoh = bundle_module.READS["spl.generators.zenoh.configurations"](inputs)
    assert kubernetes["wiring"] is zenoh["wiring"] is inputs.transport
    assert kubernetes["options"] is inputs.options


def test_a_bundle_is_the_same_with_the_transport_shared():
    first, _ = products()
    files = build_bundle(first, QUICK).files
    separately = {}
    for target in ("zenoh", "kubernetes"):
        options = BundleOptions(targets=(target,), render_diagrams=False)
        separately.update(build_bundle(first, options).files)
    for path, data in separately.items():
        if path.startswith(("zenoh/", "kubernetes/")):
            assert files[path] == data, path


def test_a_fleet_computes_its_transport_once_and_reports_what_it_skips():
    fleet = LINES / "mapping3d" / "fleets" / "lab.yaml"
    deployment = deploy(check_fleet(load_fleet(fleet)))
    inputs = FleetInputs(deployment, BundleOptions())
    shared = inputs.transport
    assert inputs.transport is shared
    assert FleetInputs(deployment, BundleOptions()).transport is not shared
    assert shared == transport(*(entry.product for entry in deployment.robots))
    assert shared.carried and inputs.skipped == {}  # the lab fleet: Zenoh carries it
    bundle = build_fleet_bundle(deployment)
    assert bundle.skipped == {} and json.loads(bundle.files["fleet.json"])["skipped"] == {}
    assert any(path.startswith("zenoh/") for path in bundle.files)
