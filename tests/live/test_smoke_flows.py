"""spl smoke, live with ROS 1, on what several containers share: a topic bridged to two
containers (fan-out), one topic fed from two containers (fan-in), a server called from
clients in two containers, and a few generated fleets with fan-out and fan-in
(tests/random_lines.fleet_specs). The rehearsal relays along the flow table's routes,
so every subscriber gets exactly its modelled publishers."""

from __future__ import annotations

import tempfile
from pathlib import Path

from hypothesis import HealthCheck, Phase, assume, given, settings

from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.random_lines import fleet_specs, write_line
from support.smoke_runs import rows_by_interface, smoke_json, write_product

ENDPOINT = 'endpoint robot_id "{id}" url "wss://x.example.org:9000/" user "u" password env "P"'
SHARED = f"""system Shared
robot container R {{
    {ENDPOINT.format(id="r1")}
    topic T : std_msgs/String name "/t"
    topic U : std_msgs/String name "/u"
    node P {{ implementation d/p publishes out -> T }}
    node Q {{ implementation d/q subscribes inp <- U calls get : nav_msgs/GetMap }}
}}
cloud container A {{
    topic T : std_msgs/String name "/t"
    topic U : std_msgs/String name "/u"
    node SA {{ implementation d/sa subscribes inp <- T publishes back -> U
               calls get : nav_msgs/GetMap }}
}}
cloud container B {{
    topic T : std_msgs/String name "/t"
    topic U : std_msgs/String name "/u"
    node SB {{ implementation d/sb subscribes inp <- T publishes back -> U }}
}}
cloud container M {{
    node Map sharing public {{ implementation d/m provides get : nav_msgs/GetMap name "/map" }}
}}
bridge R.T -> A.T
bridge R.T -> B.T
bridge A.U -> R.U
bridge B.U -> R.U
bridge R.Q.get -> M.Map.get
bridge A.SA.get -> M.Map.get
"""


def test_fan_out_fan_in_and_a_server_of_two_containers_smoke_green(tmp_path):
    line = tmp_path / "shared"
    line.mkdir()
    (line / "s.tsm").write_text(SHARED)
    (line / "s.fm").write_text("feature model Shared\nroot Shared\n")
    (line / "s.rm").write_text('resolution model Shared\ntsm "s.tsm"\nfm "s.fm"\n')
    status, report = smoke_json(write_product(line, "Shared", tmp_path / "bundle"))
    assert status == 0 and report["passed"], report["failures"]
    rows = rows_by_interface(report)
    # was: "FAIL SA inp /t data, but no modelled publisher feeds it  nothing received"
    assert rows["A.SA.inp"]["seen"].startswith("from R.P.out (")
    assert rows["B.SB.inp"]["seen"].startswith("from R.P.out (")
    fan_in = rows["R.Q.inp"]
    assert fan_in["expected"] == "from A.SA.back, B.SB.back"
    assert fan_in["seen"].startswith("from A.SA.back (") and ", from B.SB.back (" in fan_in["seen"]
    assert rows["R.Q.get"]["seen"].startswith("answered by M.Map.get (")
    assert rows["A.SA.get"]["seen"].startswith("answered by M.Map.get (")


def fans(product) -> bool:
    """A publisher whose data reaches two other containers and a subscriber fed from two."""
    out, into = {}, {}
    for flow in product.flows:
        if flow.kind.on_topic:
            out.setdefault(id(flow.source), set()).add(flow.target_container.name)
            into.setdefault(id(flow.target), set()).add(flow.source_container.name)
    return any(len(c) >= 2 for c in out.values()) and any(len(c) >= 2 for c in into.values())


@settings(
    max_examples=3,
    deadline=None,
    derandomize=True,
    phases=[Phase.explicit, Phase.generate],  # a live rehearsal each: no shrinking
    suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow],
)
@given(fleet_specs())
def test_generated_fleets_with_fan_out_and_fan_in_smoke_green(spec):
    with tempfile.TemporaryDirectory() as scratch:
        directory = write_line(spec, Path(scratch) / "line")
        product = resolve(load_product_line(directory), selection_from_list("Root")).product
        assume(fans(product))
        status, report = smoke_json(write_product(directory, "Root", Path(scratch) / "bundle"))
        assert status == 0 and report["passed"], report["failures"]
