"""A container a product drops whole changes nothing of the product: one whose nodes and
stores are all optional, which no other declaration and no resolution element refers
into, is pruned before anything looks at the architecture; so is such an optional node
in a container the product keeps. The editor's witness resolutions rely on it
(``spl.resolver.line_checks.witnesses``): an edit that adds or changes only such
declarations resolves no witness again. Checked on every shipped line
and the warehouse test line, product by product, with containers that would make a
product fail if it kept them (a robot without credentials) and that talk among
themselves (topics, a service)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.tsm import language as tsm
from spl.dsl.tsm.declarations import declarations
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import ProductLine, load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

ROOT = Path(__file__).resolve().parents[2]
LINES = [*sorted((ROOT / "product_lines").iterdir()), ROOT / "tests/models/line_checks/warehouse"]
PRODUCTS = 40  # products compared per line, in sorted order
SPARE = """
cloud container Spare group "spare" {
    topic In : std_msgs/String name "/spare/in"
    topic Out : std_msgs/String
    optional node SpareRelay {
        implementation spare_pkg/relay
        subscribes in <- In
        publishes out -> Out
        provides ask : std_srvs/Trigger
    }
    optional node SpareAsker {
        calls ask -> SpareRelay.ask
        subscribes out <- Out
    }
}

robot container SpareRobot {
    topic Scan : sensor_msgs/LaserScan
    optional node SpareLidar {
        publishes scan -> Scan
    }
}
"""


def outcome(line: ProductLine, features: str) -> tuple:
    """What a product's resolution says: its warnings, or the errors that refuse it."""
    try:
        product = resolve(line, selection_from_list(features)).product
    except ModelError as exc:
        return ("refused", tuple(str(d) for d in exc.diagnostics))
    names = [c.name for c in product.system.containers]
    assert "Spare" not in names and "SpareRobot" not in names
    return ("resolved", tuple(str(w) for w in product.warnings))


@pytest.mark.parametrize("folder", LINES, ids=lambda p: p.name)
def test_a_container_every_product_drops_changes_no_product(folder: Path, tmp_path: Path) -> None:
    line = load_product_line(folder)
    spared = tmp_path / folder.name
    shutil.copytree(folder, spared)
    template = spared / Path(line.rm.tsmPath).name
    template.write_text(template.read_text(encoding="utf-8") + SPARE, encoding="utf-8")
    extended = load_product_line(spared)
    # the rule's premise, as the editor's declarations read it
    found = declarations(tsm.check_file(template)).items
    referred = set().union(*(d.refers_to for d in found.values()))
    for name in ("Spare", "SpareRobot"):
        key = ("containers", name)
        assert found[key].droppable and key not in referred
    products = sorted(",".join(sorted(p)) for p in line.formula.products())[:PRODUCTS]
    assert products
    for features in products:
        before = outcome(line, features)
        moved = (before[0], tuple(m.replace(str(folder), str(spared)) for m in before[1]))
        assert outcome(extended, features) == moved, features


@pytest.mark.parametrize("folder", LINES, ids=lambda p: p.name)
def test_an_optional_node_nothing_refers_to_changes_no_product(
    folder: Path, tmp_path: Path
) -> None:
    """In each container with a topic, an optional node publishing and subscribing it,
    written on the line of the container's closing brace so that no other place moves:
    kept, it would feed and read the topic."""
    line = load_product_line(folder)
    spared = tmp_path / folder.name
    shutil.copytree(folder, spared)
    template = spared / Path(line.rm.tsmPath).name
    lines = template.read_text(encoding="utf-8").split("\n")
    added = []
    for container in line.tsm.containers:
        if not container.topics:
            continue
        topic = container.topics[0].name
        end = next(i for i in range(container.srcLine, len(lines)) if lines[i] == "}")
        name = f"Dropped{container.name}"
        lines[end] = (
            f"    optional node {name} {{ publishes dropped_out -> {topic} "
            f"subscribes dropped_in <- {topic} }} }}"
        )
        added.append(("containers", container.name, "nodes", name))
    assert added
    template.write_text("\n".join(lines), encoding="utf-8")
    extended = load_product_line(spared)
    found = declarations(tsm.check_file(template)).items  # the rule's premise
    referred = set().union(*(d.refers_to for d in found.values()))
    assert all(found[key].droppable and key not in referred for key in added)
    products = sorted(",".join(sorted(p)) for p in line.formula.products())[:PRODUCTS]
    for features in products:
        before = outcome(line, features)
        moved = (before[0], tuple(m.replace(str(folder), str(spared)) for m in before[1]))
        assert outcome(extended, features) == moved, features
