"""No listed product of any shipped line (every product: in
tests/generators/test_kubernetes_products.py, on the bundles it builds anyway), and no
robot of any shipped fleet, gets a private
instance nothing can feed (docs/deployment.md, "Private instances"): every private
instance Rapyuta and Kubernetes deploy is joined with its robot by a chain of flows, is
fed in its robot's deployment unless nothing in the table ever feeds it (a source), and
every private instance a robot's own data reaches is deployed. The chains are computed
from the flow table's rows and the placement rule (support/instance_chains.py), the
instances read from the files the targets write."""

from __future__ import annotations

import pytest

from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle
from spl.generators.fleet.bundle import fleet_files
from spl.resolver.fleets.deployment import deploy
from spl.resolver.fleets.fleet import check_fleet
from spl.resolver.fleets.fleet_file import load_fleet

from support.instance_chains import (
    as_vertices,
    check_instances,
    check_product_instances,
    fleet_views,
    kubernetes_instances,
    rapyuta_instances,
)
from support.shipped_products import LINES, shipped_products

FLEETS = sorted(LINES.glob("*/fleets/*.yaml"))


@pytest.mark.parametrize(
    "product",
    [pytest.param(p, id=f"{path.parents[1].name}/{path.stem}") for path, p in shipped_products()],
)
def test_no_listed_product_has_an_instance_nothing_can_feed(product):
    check_product_instances(
        product, build_bundle(product, BundleOptions(render_diagrams=False)).files
    )


@pytest.mark.parametrize("path", FLEETS, ids=lambda p: f"{p.parents[1].name}/{p.stem}")
def test_no_robot_of_a_shipped_fleet_has_an_instance_nothing_can_feed(path):
    check = check_fleet(load_fleet(path))
    assert check.ok, check.diagnostics
    deployment = deploy(check)
    files = fleet_files(deployment)
    views, private = fleet_views(deployment)
    kubernetes = as_vertices(kubernetes_instances(files))
    assert kubernetes == as_vertices(rapyuta_instances(files, private))
    check_instances(views, kubernetes)
