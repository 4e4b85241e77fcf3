"""Names of the stand-ins ``spl smoke`` starts, and of the endpoint interfaces bridges
create, are unique by construction.

Two regressions, from a product line written for the purpose:

* a node named ``endpoint`` met the container's endpoint stand-in, also ``/endpoint``:
  the master shut one down ("new node registered with same name") and the two nodes'
  interface ids met, so the cloud subscriber fed through the bridge was expected to
  get no data at all;
* two migrated clients of ``Db.get`` in two cloud containers needed two endpoint
  stand-ins both named ``srv_Db_get``: the engine made one, bridged to both servers,
  so one client was answered by the other container's server, ``resolved.tsm`` did not
  parse back, and the Rapyuta file connected the robot to one server only.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from spl.dsl.tsm import language as tsm_language
from spl.dsl.tsm.printer import print_model
from spl.generators.bundle.writer import bundle_files
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list
from spl.smoke.plan import endpoint_name
from spl.smoke.planning import load_plan

from support.smoke_runs import rows_by_interface, smoke_json, write_product

TSM = """system Clash

robot container Robot {
    endpoint robot_id "robot_1" url "wss://cloud.example.org:9000/" user "robot"
             password env "RCE_PASSWORD"
    topic Scan : sensor_msgs/LaserScan name "/scan"
    node endpoint {
        implementation urg_node/urg_node
        publishes scan -> Scan
    }
}

cloud container C1 {
    topic Scan : sensor_msgs/LaserScan name "/scan"
    node Mapper {
        implementation survey/mapper
        subscribes scan <- Scan
    }
    node Db {
        implementation db/db
        provides get : std_srvs/Trigger name "/c1/get"
    }
    node UserA {
        implementation user/a
        calls get -> Db.get
    }
}

cloud container C2 {
    node Db {
        implementation db/db
        provides get : std_srvs/Trigger name "/c2/get"
    }
    node UserB {
        implementation user/b
        calls get -> Db.get
    }
}

bridge Robot.Scan -> C1.Scan
"""
FM = "feature model Clash\nroot Base {\n    optional OnBoard\n}\n"
RM = """resolution model Clash
tsm "clash.tsm"
fm "clash.fm"

when OnBoard selected {
    migrate C1.UserA to Robot
    migrate C2.UserB to Robot
}
"""


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("clash")
    for name, text in (("clash.tsm", TSM), ("clash.fm", FM), ("clash.rm", RM)):
        (folder / name).write_text(text, encoding="utf-8")
    return write_product(folder, "Base,OnBoard", folder / "bundle")


def test_the_endpoint_stand_in_takes_a_name_no_node_has(bundle: Path) -> None:
    plan = load_plan(bundle)
    endpoints = {c.name: c.endpoint.ros_name for c in plan.containers if c.endpoint}
    assert endpoints == {"Robot": "/endpoint_2", "C1": "/endpoint", "C2": "/endpoint"}
    ids = [i.id for i in plan.interfaces()]
    assert len(ids) == len(set(ids))
    found = {i.id: i for i in plan.interfaces()}
    assert found["C1.Mapper.scan"].sources == ("Robot.endpoint.scan",)
    (relay,) = found["Robot.endpoint_2.sub_Scan"].relays
    assert (relay.container, relay.interface) == ("C1", "pub_Scan")
    assert endpoint_name({"endpoint", "/ns/endpoint_2"}, "/ns") == "endpoint_3"


def test_two_servers_of_one_name_get_two_stand_ins(bundle: Path) -> None:
    text = (bundle / "resolved.tsm").read_text(encoding="utf-8")
    assert "bridge Robot.UserA.get -> C1.Db.get" in text
    assert "bridge Robot.UserB.get -> C2.Db.get" in text
    system = tsm_language.parse_text(text, "resolved.tsm")  # parses back, same names
    robot = next(c for c in system.containers if c.name == "Robot")
    assert sorted(i.name for i in robot.endpoint.interfaces) == [
        "srv_C2_Db_get",
        "srv_Db_get",
        "sub_Scan",
    ]
    found = {i.id: i for i in load_plan(bundle).interfaces()}
    assert found["Robot.UserA.get"].server == "C1.Db.get"
    assert found["Robot.UserB.get"].server == "C2.Db.get"
    rapyuta = json.loads((bundle / "rapyuta" / "Robot.json").read_text(encoding="utf-8"))
    assert {(c["tagA"], c["tagB"]) for c in rapyuta["connections"]} >= {
        ("robot_1/srv_Db_get", "C1_robot_1/cli_Db_get"),
        ("robot_1/srv_C2_Db_get", "C2_robot_1/cli_Db_get"),
    }


def test_template_bridges_whose_names_coincide_are_told_apart() -> None:
    """Once a located error ("endpoint interface name srv_a_b_c ... already used by
    another bridge"); now each bridge has its own stand-in, and the printed model
    parses back to the same names."""
    text = """system S
robot container R {
    node N {
        implementation p/n
        calls a : std_srvs/Empty
        calls b : std_srvs/Empty
    }
}
cloud container C {
    node a_b {
        implementation p/ab
        provides c : std_srvs/Empty
    }
    node a {
        implementation p/a
        provides b_c : std_srvs/Empty
    }
}
bridge R.N.a -> C.a_b.c
bridge R.N.b -> C.a.b_c
"""
    system = tsm_language.parse_text(text, "s.tsm")
    names = {c.name: [i.name for i in c.endpoint.interfaces] for c in system.containers}
    assert names == {"R": ["srv_a_b_c", "srv_C_a_b_c"], "C": ["cli_a_b_c", "cli_C_a_b_c"]}
    (node,) = system.containers[0].nodes
    served = {i.name: i.server.name for i in node.interfaces}
    assert served == {"a": "srv_a_b_c", "b": "srv_C_a_b_c"}
    again = tsm_language.parse_text(print_model(system), "again.tsm")
    assert print_model(again) == print_model(system)


def test_resolving_twice_gives_the_same_bytes(bundle: Path) -> None:
    folder = bundle.parent
    product = resolve(load_product_line(folder), selection_from_list("Base,OnBoard")).product
    files = bundle_files(product)
    assert files["resolved.tsm"] == (bundle / "resolved.tsm").read_bytes()
    assert files["rapyuta/Robot.json"] == (bundle / "rapyuta" / "Robot.json").read_bytes()


def test_smoke_runs_green_with_the_clashing_names(bundle: Path) -> None:
    status, report = smoke_json(bundle)
    assert status == 0 and report["passed"], report["failures"]
    rows = rows_by_interface(report)
    assert rows["Robot.endpoint_2.sub_Scan"]["ok"]
    assert rows["C1.Mapper.scan"]["seen"].startswith("from Robot.endpoint.scan (")
    assert rows["Robot.UserA.get"]["seen"].startswith("answered by C1.Db.get (")
    assert rows["Robot.UserB.get"]["seen"].startswith("answered by C2.Db.get (")
