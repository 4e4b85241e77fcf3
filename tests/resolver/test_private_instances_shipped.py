"""No product of any shipped line, and no robot of any shipped fleet, gets a private
instance nothing can feed (docs/deployment.md, "Private instances"): every private
instance Rapyuta and Kubernetes deploy is joined with its robot by a chain of flows, is
fed in its robot's deployment unless nothing in the table ever feeds it (a source), and
every private instance a robot's own data reaches is deployed. The chains are computed
from the flow table's rows and the placement rule (support/instance_chains.py), the
instances read from the files the targets write."""

from __future__ import annotations

import pytest

from spl.generators.bundle import build_bundle
from spl.generators.fleet import fleet_files
from spl.resolver.fleet import check_fleet
from spl.resolver.fleet_deployment import deploy
from spl.resolver.fleet_file import load_fleet

from support.instance_chains import (
    Vertex,
    as_vertices,
    chained,
    fed_by_robot,
    idle,
    kubernetes_instances,
    rapyuta_instances,
    robot_views,
)
from support.shipped_products import LINES, shipped_products

FLEETS = sorted(LINES.glob("*/fleets/*.yaml"))


def check_instances(views, deployed: set[Vertex]) -> None:
    for view in views.values():
        tags = {tag for tag, _ in view.candidates}
        mine = {v for v in deployed if v[0] in tags}
        assert chained(view, mine) == mine, view.robot_id
        assert not idle(view, mine), (view.robot_id, sorted(idle(view, mine)))
        assert fed_by_robot(view) <= mine, view.robot_id


@pytest.mark.parametrize(
    "product",
    [pytest.param(p, id=f"{path.parents[1].name}/{path.stem}") for path, p in shipped_products()],
)
def test_no_listed_product_has_an_instance_nothing_can_feed(product):
    views = robot_views(product)
    private = {tag for view in views.values() for tag, _ in view.candidates}
    files = build_bundle(product, render_diagrams=False).files
    kubernetes = as_vertices(kubernetes_instances(files))
    assert kubernetes == as_vertices(rapyuta_instances(files, private))
    check_instances(views, kubernetes)


@pytest.mark.parametrize("path", FLEETS, ids=lambda p: f"{p.parents[1].name}/{p.stem}")
def test_no_robot_of_a_shipped_fleet_has_an_instance_nothing_can_feed(path):
    check = check_fleet(load_fleet(path))
    assert check.ok, check.diagnostics
    deployment = deploy(check)
    files = fleet_files(deployment)
    views = {}
    for entry in deployment.robots:
        views |= robot_views(entry.product)
    private = {tag for view in views.values() for tag, _ in view.candidates}
    kubernetes = as_vertices(kubernetes_instances(files))
    assert kubernetes == as_vertices(rapyuta_instances(files, private))
    check_instances(views, kubernetes)
