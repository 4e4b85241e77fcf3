"""A product's copy of its template leaves out what the product drops before anything
reads it (an optional node or store nothing else in the template refers into, which no
active resolution element names: spl.resolver.resolution.pruning), and the product is the same as
the one resolved from a whole copy: the same resolved model (printed), warnings or
errors, trace, nodes kept and removed, migrations and flows. Compared on every product
(up to a bound) of the shipped lines and the test lines, on random lines
(support/random_lines.py), and on a migration onto the name of a node left out.

The whole copy is the engine's own path for a line whose template has no such node:
the line's index of them (``ProductLine.unreferred_optionals``) is emptied."""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import given, settings

from spl.core.diagnostics import ModelError
from spl.dsl.tsm.printer import print_model
from spl.resolver.resolution.context import qualified
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import ProductLine, load_product_line
from spl.resolver.resolution.product_selection import selection_from_list
from spl.resolver.resolution.pruning import left_out

from support.hypothesis_budget import examples
from support.random_lines import line_specs, write_line

ROOT = Path(__file__).resolve().parents[2]
LINES = [
    *sorted(p for p in (ROOT / "product_lines").iterdir() if p.is_dir()),
    *(ROOT / "tests/models" / name for name in ("offshore", "windfarm", "launch")),
    ROOT / "tests/models/line_checks/warehouse",
    ROOT / "tests/models/resolver/migrations",
]
PRODUCTS = 60  # products compared per line, in sorted order


def whole_copy(line: ProductLine) -> ProductLine:
    """The same line, its products resolved from a whole copy of the template."""
    again = load_product_line(line.directory)
    again.__dict__["unreferred_optionals"] = {}  # the cached index: no node to leave out
    return again


def outcome(line: ProductLine, features: str) -> tuple:
    """Everything a product's resolution says, as text."""
    try:
        resolution = resolve(line, selection_from_list(features))
    except ModelError as exc:
        return ("refused", tuple(str(d) for d in exc.diagnostics))
    product = resolution.product
    flows = product.flows
    return (
        "resolved",
        print_model(product.system),
        tuple(str(w) for w in product.warnings),
        tuple(str(e) for e in resolution.trace.entries),
        resolution.kept_nodes,
        resolution.removed_nodes,
        tuple(str(m) for m in product.migrations),
        product.left_out,
        tuple(
            (f.kind, qualified(f.source), qualified(f.target), f.routes, len(f.route))
            for f in flows or ()
        ),
        tuple(qualified(c) for c in flows.unserved) if flows is not None else (),
    )


def same_products(line: ProductLine, limit: int = PRODUCTS) -> int:
    """Compares the products of ``line`` resolved both ways; how many left a node out."""
    whole = whole_copy(line)
    products = sorted(",".join(sorted(p)) for p in line.formula.products())[:limit]
    assert products
    leaving = 0
    for features in products:
        assert outcome(line, features) == outcome(whole, features), features
        active = [
            e
            for e in line.rm.elements
            if (e.feature.name in features.split(",")) == e.activeIfSelected
        ]
        leaving += bool(left_out(line.unreferred_optionals, active))
    return leaving


@pytest.mark.parametrize("folder", LINES, ids=lambda p: p.name)
def test_a_product_copied_without_what_it_drops_is_the_same(folder: Path) -> None:
    same_products(load_product_line(folder))


@settings(max_examples=examples(40), deadline=None)
@given(line_specs())
def test_random_products_copied_without_what_they_drop_are_the_same(spec) -> None:  # type: ignore[no-untyped-def]
    with tempfile.TemporaryDirectory() as tmp:
        line = load_product_line(write_line(spec, Path(tmp)))
        same_products(line, limit=16)


MIGRATION_TSM = """system Clash

robot container Robot {
    topic Scan : sensor_msgs/LaserScan
    node Planner {
        publishes plan -> Scan
    }
}

cloud container Cloud group "cloud" {
    topic Scan : sensor_msgs/LaserScan
    optional node Spare {
        publishes plan -> Scan
    }
    node Mapper {
        subscribes scan <- Scan
    }
}

bridge Robot.Scan -> Cloud.Scan
"""
MIGRATION_FM = """feature model Clash

root Root {
    optional Offload
    optional Local
}
"""
MIGRATION_RM = """resolution model Clash
tsm "clash.tsm"
fm "clash.fm"

when Offload selected {
    migrate Robot.Planner to Cloud
}

when Local selected {
    require Cloud.Spare
}
"""


def test_a_migration_onto_the_name_of_a_node_left_out_is_refused(tmp_path: Path) -> None:
    """The cloud's optional node is left out of the copy when Local is not selected;
    moving the robot's Planner there is refused all the same when it has that name. The
    .rm's checks refuse such a line on loading, so the name is given after it loaded:
    the engine's own check is what is tested."""
    for name, text in (("tsm", MIGRATION_TSM), ("fm", MIGRATION_FM), ("rm", MIGRATION_RM)):
        (tmp_path / f"clash.{name}").write_text(text, encoding="utf-8")
    line = load_product_line(tmp_path)
    whole = whole_copy(line)
    for each in (line, whole):
        cloud = next(c for c in each.tsm.containers if c.name == "Cloud")
        next(n for n in cloud.nodes if n.name == "Spare").name = "Planner"
    left = left_out(line.unreferred_optionals, [line.rm.elements[0]])
    assert len(left) == 1  # the cloud's Planner, when only Offload's element is active
    refused = outcome(line, "Offload,Root")
    assert refused == outcome(whole, "Offload,Root")
    assert refused[0] == "refused"
    message = refused[1][0]
    assert "cannot migrate Planner to Cloud: container Cloud already has a node Planner" in message
    assert "clash.tsm:12:" in message  # the cloud's own Planner, left out of the copy
