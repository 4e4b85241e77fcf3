"""On random lines of two or three robots and clouds of every sharing mode
(support/random_lines.py), and on fleets of two robots of such a line, every private
instance a target deploys (Rapyuta, Kubernetes, Zenoh, the fleet's robot launch files)
has a chain of flows to its robot, and no instance a robot's own data reaches is
missing (docs/deployment.md, "Private instances"). The chains are computed here
(support/instance_chains.py) from the flow table's rows and the placement rule, not with
the resolver's decision; the targets are read from the files they write."""

from __future__ import annotations

import tempfile
from pathlib import Path

from hypothesis import event, given, settings, strategies as st, target

from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle
from spl.generators.fleet.bundle import fleet_files
from spl.resolver.fleets.deployment import deploy
from spl.resolver.fleets.fleet import check_fleet
from spl.resolver.fleets.fleet_file import load_fleet
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.hypothesis_budget import examples
from support.instance_chains import (
    Vertex,
    as_vertices,
    chained,
    fed_by_robot,
    fleet_views,
    kubernetes_instances,
    launch_instances,
    rapyuta_instances,
    robot_views,
    zenoh_places,
)
from support.random_lines import fleet_specs, write_line


def check_instances(views, deployed: set[Vertex], what: str) -> int:
    """Each robot's deployed private instances are chained to it; none it feeds is
    missing. Returns how many instances the robots do not get."""
    left_out = 0
    for view in views.values():
        tags = {tag for tag, _ in view.candidates}
        mine = {v for v in deployed if v[0] in tags}
        assert chained(view, mine) == mine, (
            f"{what}: {view.robot_id} gets instances no flow chain joins with it"
        )
        missing = fed_by_robot(view) - mine
        assert not missing, (
            f"{what}: {view.robot_id} feeds {sorted(missing)}, which are not deployed"
        )
        left_out += len(view.candidates - mine)
    event(f"{what}: {'some' if left_out else 'no'} instances left out")
    return left_out


@st.composite
def cases(draw):
    spec = draw(fleet_specs())
    selected = draw(st.sets(st.sampled_from(spec.features()))) if spec.elements else set()
    return spec, selected, draw(st.booleans())


@settings(max_examples=examples(40), deadline=None)
@given(cases())
def test_every_private_instance_of_every_target_is_chained_to_its_robot(case):
    spec, selected, as_fleet = case
    with tempfile.TemporaryDirectory() as scratch:
        folder = write_line(spec, Path(scratch) / "line")
        features = ",".join(["Root", *sorted(selected)])
        product = resolve(load_product_line(folder), selection_from_list(features)).product
        views = robot_views(product)
        private = {tag for view in views.values() for tag, _ in view.candidates}
        bundle = build_bundle(product, BundleOptions(render_diagrams=False))
        files = bundle.files
        kubernetes = as_vertices(kubernetes_instances(files))
        rapyuta = as_vertices(rapyuta_instances(files, private))
        assert kubernetes == rapyuta
        target(float(check_instances(views, kubernetes, "product")), label="instances left out")
        if "zenoh/" not in bundle.skipped:  # a bridge only where an instance is deployed
            assert zenoh_places(files) & private <= {tag for tag, _ in kubernetes}
        if as_fleet:
            fleet_of(folder, features, Path(scratch))


def fleet_of(line: Path, features: str, scratch: Path) -> None:
    """Two robots of the product, in two groups: the fleet's bundle deploys each robot's
    private instances as its own product's chains allow."""
    path = scratch / "fleet.yaml"
    path.write_text(
        f"fleet: pair\nproduct_line: {line}\nrobots:\n"
        f"  a: {{group: g1, features: [{features}]}}\n"
        f"  b: {{group: g2, features: [{features}]}}\n"
    )
    check = check_fleet(load_fleet(path))
    if not check.ok:
        event("fleet refused")
        return
    deployment = deploy(check)
    files = fleet_files(deployment)
    views, private = fleet_views(deployment)
    kubernetes = as_vertices(kubernetes_instances(files))
    rapyuta = as_vertices(rapyuta_instances(files, private))
    launched: set[Vertex] = set()
    for name in ("a", "b"):
        launched |= as_vertices(launch_instances(files, f"robots/{name}/", private))
    assert kubernetes == rapyuta == launched
    check_instances(views, kubernetes, "fleet")
    event("fleet deployed")
