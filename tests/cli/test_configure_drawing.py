"""The configurator's architecture drawing (src/spl/configure/drawing.py): well-formed SVG
for every listed product of every shipped line, the same bytes for the same product,
and the marks a reader needs: migrated nodes with their origin, removed nodes and
containers (with pruning's reason), the bridges between containers."""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

from spl import pipeline
from spl.configure.drawing import architecture_svg
from spl.resolver.resolution.product_selection import load_selection_file

ROOT = Path(__file__).resolve().parents[2]
SVG = "{http://www.w3.org/2000/svg}"
PRODUCTS = sorted(ROOT.glob("product_lines/*/products/*.yaml"))


def drawing(product: Path) -> str:
    line = pipeline.load_line(product.parent.parent)
    return architecture_svg(pipeline.resolve_product(line, load_selection_file(product)))


@pytest.mark.parametrize("product", PRODUCTS, ids=lambda p: f"{p.parent.parent.name}/{p.stem}")
def test_every_shipped_product_draws_well_formed_and_deterministic_svg(product: Path) -> None:
    first = drawing(product)
    assert drawing(product) == first
    root = ElementTree.fromstring(first)
    assert root.tag == f"{SVG}svg"
    line = pipeline.load_line(product.parent.parent)
    resolution = pipeline.resolve_product(line, load_selection_file(product))
    drawn = {g.get("data-container") for g in root.iter(f"{SVG}g") if g.get("data-container")}
    assert drawn == {c.name for c in resolution.product.system.containers}
    nodes = {g.get("data-node") for g in root.iter(f"{SVG}g") if g.get("data-node")}
    assert nodes == {n.name for c in resolution.product.system.containers for n in c.nodes}


def test_migrated_and_removed_nodes_and_bridges_are_marked() -> None:
    svg = drawing(ROOT / "product_lines" / "mapping3d" / "products" / "youbot_stereo_room.yaml")
    assert '<g data-node="MapOptimizer" data-migrated="MappingCloud">' in svg
    assert "migrated from MappingCloud" in svg
    assert 'data-node-removed="DepthCamera"' in svg
    assert '<g data-bridge="Robot MappingCloud">' in svg
    resolution = pipeline.resolve_product(
        pipeline.load_line(ROOT / "product_lines" / "mapping3d"),
        load_selection_file(ROOT / "product_lines" / "mapping3d" / "products" /
                            "youbot_stereo_room.yaml"),
    )  # fmt: skip
    assert f"{len(resolution.product.system.connections)} bridges" in svg


def test_containers_left_out_are_listed_with_the_reason() -> None:
    svg = drawing(ROOT / "product_lines" / "orchard" / "products" / "onboard_soft.yaml")
    assert ('data-left-out="Scout">Scout: robot container left with no node in this '
            "product: not deployed</text>") in svg  # fmt: skip
    assert 'data-left-out="OrchardCloud"' in svg
    assert 'data-container="Scout"' not in svg  # pruned from the system: not drawn as one
