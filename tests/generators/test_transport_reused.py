"""A bundle's Zenoh and Kubernetes generators share one computation of the product's
transport: within ``transport_reused()`` the same systems give the same Transport, other
systems their own; outside, each call computes anew."""

from __future__ import annotations

from pathlib import Path

from spl.generators.bundle import build_bundle
from spl.generators.zenoh_bridge import transport, transport_reused
from spl.resolver.engine import resolve
from spl.resolver.product_line import load_product_line
from spl.resolver.product_selection import load_selection_file

LINES = Path(__file__).resolve().parents[2] / "product_lines"


def products():
    line = load_product_line(LINES / "mapping3d")
    paths = sorted((LINES / "mapping3d" / "products").glob("*.yaml"))[:2]
    return [resolve(line, load_selection_file(path)).product for path in paths]


def test_one_transport_per_system_within_and_a_new_one_outside():
    first, second = products()
    outside = transport(first)
    assert transport(first) is not outside
    with transport_reused():
        shared = transport(first)
        assert transport(first) is shared
        other = transport(second)
        assert other is not shared
        assert transport(second) is other
    assert transport(first) is not shared
    assert shared == outside  # the same result, computed once


def test_a_bundle_is_the_same_with_the_transport_shared():
    first, _ = products()
    files = build_bundle(first, render_diagrams=False).files
    separately = {}
    for target in ("zenoh", "kubernetes"):
        separately.update(build_bundle(first, (target,), render_diagrams=False).files)
    for path, data in separately.items():
        if path.startswith(("zenoh/", "kubernetes/")):
            assert files[path] == data, path
