"""The fleet rules on a small line where a shared node can be migrated, rewired to another
server and given a parameter from an attribute; and the SAT options agree with the check
for every product a robot could choose."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.fm.language import all_features
from spl.resolver.analysis.formula import enumerate_products
from spl.resolver.fleets.fleet import check_fleet
from spl.resolver.fleets.fleet_file import load_fleet
from spl.resolver.fleets.options import _build, fleet_options
from spl.resolver.resolution.effects import Settings

ROOT = Path(__file__).resolve().parents[2]
TSM = """system S
robot container R {
    endpoint robot_id "r" url "wss://x.org:9000/" user "u" password env "P"
    topic T : std_msgs/String name "/t"
    node Talker {
        implementation pkg/talker
        publishes out -> T
    }
}
cloud container C group "g" {
    topic T : std_msgs/String name "/t"
    node Store {
        implementation pkg/store
        provides get : std_srvs/Trigger name "/store/get"
    }
    optional node Store2 {
        implementation pkg/store2
        provides get : std_srvs/Trigger name "/store2/get"
    }
    node Planner {
        implementation pkg/planner
        param rate : double = 1.0
        subscribes heard <- T
        calls get -> Store.get
    }
}
bridge R.T -> C.T
"""
FM = """feature model S
root S {
    mandatory Shared { sharing protected }
    optional Onboard
    optional Alt
    optional Fast { attribute rate : double = 5.0 }
}
"""
RM = """resolution model S
tsm "s.tsm"
fm "s.fm"
when Shared selected { require Planner, Store }
when Alt selected {
    require Store2
    connect Planner.get to server Store2.get
}
when Onboard selected { migrate Planner to R }
when Fast selected { parameter Planner.rate = feature Fast.rate }
"""


@pytest.fixture
def line(tmp_path: Path) -> Path:
    directory = tmp_path / "line"
    directory.mkdir()
    for name, text in (("s.tsm", TSM), ("s.fm", FM), ("s.rm", RM)):
        (directory / name).write_text(text)
    return directory


def write_fleet(line: Path, robots: str) -> Path:
    path = line.parent / "fleet.yaml"
    path.write_text(f"fleet: f\nproduct_line: line\nrobots:\n{robots}")
    return path


def errors(path: Path) -> list[str]:
    return [d.message for d in check_fleet(load_fleet(path)).diagnostics]


def test_a_shared_node_migrated_by_one_robot_only_is_a_conflict(line) -> None:
    found = errors(write_fleet(line, "  a: {features: [Shared]}\n  b: {features: [Onboard]}\n"))
    (message,) = found
    assert message.startswith(
        "conflict on shared node Planner: robots a and b ask for a "
        "different placement: a has C_default, protected for group default"
    )
    assert "b has on robot container R (migrated by feature Onboard: 'when Onboard selected'" in (
        message
    )
    both = write_fleet(line, "  a: {features: [Onboard]}\n  b: {features: [Onboard, Alt]}\n")
    assert errors(both) == []  # nobody shares a node both run on board


def test_a_shared_client_rewired_to_another_server_is_a_conflict(line) -> None:
    (message,) = errors(write_fleet(line, "  a: {features: [Shared]}\n  b: {features: [Alt]}\n"))
    assert "ask for a different server of get" in message
    assert "a has Store.get running in C (as the template has it (" in message
    assert "b has Store2.get running in C (by feature Alt: 'when Alt selected'" in message


def test_parameters_set_from_attributes_must_agree(line) -> None:
    robots = (
        "  a: {features: [Fast], attributes: {Fast.rate: 2.0}}\n"
        "  b: {features: [Fast], attributes: {Fast.rate: 3}}\n"
        "  c: {group: other, features: [Fast], attributes: {Fast.rate: 3}}\n"
        "  d: {features: [Fast], attributes: {Fast.rate: 2}, sharing: {Shared: private}}\n"
    )
    (message,) = errors(write_fleet(line, robots))
    assert "robots a and b ask for a different parameter rate: a has 2.0" in message
    assert "b has 3.0 (by feature Fast: 'when Fast selected'" in message


def test_options_use_the_robots_own_attributes(line) -> None:
    path = write_fleet(
        line,
        "  a: {features: [Fast], attributes: {Fast.rate: 2.0}}\n"
        "  b: {features: [Fast], attributes: {Fast.rate: 2.0}}\n",
    )
    fleet = load_fleet(path)
    changed = fleet_options(fleet, "b")
    assert changed.joinable
    assert {o.feature: o.status for o in changed.options} == {
        "Onboard": "forbidden",
        "Alt": "forbidden",
        "Fast": "forced",
    }
    newcomer = fleet_options(fleet, "c")  # no attributes: rate 5.0 with Fast, 1.0 without
    assert not newcomer.joinable
    assert newcomer.blocking == (
        "Planner must have parameter rate 2.0, as a fixed it (C_default, protected for group "
        "default)",
    )
    assert newcomer.alternatives == ("Shared: private",)


def test_options_refuse_a_fleet_whose_robots_do_not_resolve(line) -> None:
    path = write_fleet(line, "  a: {features: [Nope]}\n")
    with pytest.raises(ModelError) as info:
        fleet_options(load_fleet(path), "b")
    assert "robot a: unknown feature 'Nope'" in str(info.value)


def agreement(path: Path, robot_group: str) -> int:
    """For every product and sharing mode of a robot joining the fleet: the SAT encoding
    admits it exactly when the fleet check accepts the fleet with that robot added."""
    fleet = load_fleet(path)
    check = check_fleet(fleet)
    assert check.ok
    compared = 0
    shared = [f.name for f in all_features(check.line.fm) if f.sharing is not None]
    for features in enumerate_products(check.line.fm):
        for mode in (None, "private", "protected", "public"):
            sharing = {f: mode for f in shared if f in features} if mode else {}
            encoding, _ = _build(check, None, robot_group, Settings.of(sharing, {}))
            cnf = encoding.cnf
            assumptions = [cnf.var[n] if n in features else -cnf.var[n] for n in cnf.names]
            admitted = encoding.solver.solve(assumptions=assumptions + list(encoding.selectors))
            encoding.solver.delete()
            listed = ", ".join(sorted(features))
            extra = f"  newcomer: {{group: {robot_group}, features: [{listed}]"
            extra += f", sharing: {{{', '.join(f'{f}: {m}' for f, m in sharing.items())}}}}}\n"
            with_robot = path.parent / "with.yaml"
            with_robot.write_text(path.read_text() + extra)
            accepted = check_fleet(load_fleet(with_robot)).ok
            assert admitted == accepted, (listed, sharing, robot_group)
            compared += 1
    return compared


@pytest.mark.parametrize(
    "robots",
    [
        "  a: {features: [Shared]}\n"
        "  p: {group: other, features: [Alt], sharing: {Shared: public}}\n",
        "  a: {features: [Onboard, Fast], attributes: {Fast.rate: 2}}\n"
        "  p: {group: other, features: [Fast], sharing: {Shared: public}}\n",
    ],
    ids=["in the cloud", "on board"],
)
@pytest.mark.parametrize("group", ["default", "other"])
def test_sat_options_agree_with_the_check_on_the_small_line(line, robots, group) -> None:
    assert agreement(write_fleet(line, robots), group) > 30


def test_sat_options_agree_with_the_check_on_mapping3d(tmp_path) -> None:
    path = tmp_path / "fleet.yaml"
    path.write_text(
        f"fleet: f\nproduct_line: {ROOT / 'product_lines' / 'mapping3d'}\nrobots:\n"
        "  y: {group: lab, features: [YouBot, Depth, Room]}\n"
        "  r: {group: hall, features: [Roomba, Depth, Corridor], sharing: {SharedMap: public}}\n"
    )
    assert agreement(path, "lab") == 48
