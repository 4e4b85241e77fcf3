"""The effects model (what each resolution element does to each node) predicts the
resolved products exactly: every node's presence, placement, sharing mode,
implementation, parameters, topics and servers, for every product of both shipped lines
and every sharing mode of the features that have one."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.dsl.fm.language import all_features
from spl.resolver.analysis.formula import enumerate_products
from spl.resolver.resolution.effects import LineEffects, Settings, active_in, observed, origin_of
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import ProductSelection

ROOT = Path(__file__).resolve().parents[2]
LINES = sorted((ROOT / "product_lines").iterdir())


@pytest.mark.parametrize("directory", LINES, ids=lambda p: p.name)
def test_prediction_equals_resolution_for_every_product(directory: Path) -> None:
    line = load_product_line(directory)
    effects = LineEffects(line)
    shared = [f.name for f in all_features(line.fm) if f.sharing is not None]
    compared = 0
    for features in enumerate_products(line.fm):
        for mode in (None, "private", "protected", "public"):
            sharing = {f: mode for f in shared if f in features} if mode else {}
            resolution = resolve(line, ProductSelection("p", sorted(features), sharing=sharing))
            product = resolution.product
            active = active_in(set(product.features))
            settings = Settings.of(sharing, {})
            present = set()
            for container in product.system.containers:
                for node in container.nodes:
                    key = (origin_of(node, product), node.name)
                    present.add(key)
                    model = effects.nodes[key]
                    assert model.present(active), key
                    assert effects.predict(model, active, settings) == observed(node, product)
                    compared += 1
            absent = {k for k, m in effects.nodes.items() if not m.present(active)}
            assert absent == set(effects.nodes) - present
    assert compared > 100


TSM = """system S
robot container R {
    endpoint robot_id "r" url "wss://x.org:9000/" user "u" password env "P"
    topic T : std_msgs/String name "/t"
    node Talker {
        implementation pkg/talker
        publishes out -> T
    }
}
cloud container C {
    topic T : std_msgs/String name "/t"
    node Planner sharing protected {
        implementation pkg/planner
        param rate : double = 1.0
        subscribes heard <- T
    }
}
bridge R.T -> C.T
"""
FM = "feature model S\nroot S { optional Fast { attribute rate : double = 5.0 } }\n"
RM = """resolution model S
tsm "s.tsm"
fm "s.fm"
when Fast selected { parameter Planner.rate = feature Fast.rate }
"""


@pytest.mark.parametrize("given", [{}, {"Fast.rate": 7}, {"Fast.rate": 0.25}])
def test_a_parameter_set_from_an_attribute_takes_the_robot_value(tmp_path, given) -> None:
    for name, text in (("s.tsm", TSM), ("s.fm", FM), ("s.rm", RM)):
        (tmp_path / name).write_text(text)
    line = load_product_line(tmp_path)
    effects = LineEffects(line)
    planner = effects.nodes[("C", "Planner")]
    selection = ProductSelection("p", ["Fast"], attributes=dict(given))
    product = resolve(line, selection).product
    node = next(n for c in product.system.containers for n in c.nodes if n.name == "Planner")
    predicted = effects.predict(planner, active_in(set(product.features)), Settings.of({}, given))
    assert predicted == observed(node, product)
    assert predicted["parameter rate"] == repr(float(given.get("Fast.rate", 5.0)))
