"""``spl import graph`` of an action from a live ROS 1 graph (docs/import.md, "A live
graph"): a real roscore, and a real actionlib SimpleActionServer and SimpleActionClient
(Debian's ``python3-actionlib``, on the action type ``actionlib/TwoInts`` it ships)
started by roslaunch. The five topics actionlib makes become ``provides action`` on the
server and ``calls action ... -> SERVER`` on the client; the line passes ``spl check``,
and ``spl smoke`` of its product brings the action up green: goals answered by the
server, result and feedback back at the client. ``spl import launch --graph`` of the
launch file that started them says the same.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from spl.pipeline import check_models

from support.launch_round_trip import import_launch, stub_packages
from support.live_master import launched, system_state, wait_for, write_nodes
from support.smoke_runs import (
    rows_by_interface,
    smoke_json,
    spl_command,
    write_product,
)

NODES = {
    "adder.py": """import actionlib
import rospy
from actionlib.msg import TwoIntsAction, TwoIntsResult
rospy.init_node("adder")
def execute(goal):
    server.set_succeeded(TwoIntsResult(sum=goal.a + goal.b))
server = actionlib.SimpleActionServer("add", TwoIntsAction, execute, auto_start=False)
server.start()
rospy.spin()
""",
    "asker.py": """import actionlib
import rospy
from actionlib.msg import TwoIntsAction, TwoIntsGoal
rospy.init_node("asker")
client = actionlib.SimpleActionClient("add", TwoIntsAction)
client.wait_for_server()
while not rospy.is_shutdown():
    client.send_goal_and_wait(TwoIntsGoal(a=1, b=2))
    rospy.sleep(0.5)
""",
}
LAUNCH = """<launch>
  <node pkg="adding" type="adder.py" name="adder"/>
  <node pkg="adding" type="asker.py" name="asker"/>
</launch>
"""
TOPICS = {f"/add/{part}" for part in ("goal", "cancel", "status", "feedback", "result")}


@pytest.fixture(scope="module")
def live_graph(tmp_path_factory):
    folder = tmp_path_factory.mktemp("graph")
    packages = stub_packages(folder / "packages", "adding")
    write_nodes(packages / "adding" / "scripts", NODES)
    launch = packages / "adding" / "adding.launch"
    launch.write_text(LAUNCH)
    with launched(folder, packages, launch) as master:

        def registered() -> bool:
            # each of the five topics has its publisher and its subscriber
            state = system_state(master)
            return state is not None and all({t for t, _ in side} >= TOPICS for side in state[:2])

        wait_for("the action's topics", registered)
        yield master, packages, launch


def test_an_actionlib_action_imports_as_an_action_and_smokes_green(live_graph, tmp_path: Path):
    master, packages, _ = live_graph
    out = tmp_path / "adding"
    done = subprocess.run([*spl_command(), "import", "graph", "-o", str(out), "--master",
                           master, "--package-path", str(packages)], capture_output=True,
                          text=True, timeout=300)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("imported adding: 1 product, 2 nodes, 0 things")
    tsm = (out / "adding.tsm").read_text()
    assert (
        "node adder {\n        implementation adding/adder.py\n"
        '        provides action add : actionlib/TwoInts name "/add"\n    }'
    ) in tsm
    assert (
        "node asker {\n        implementation adding/asker.py\n"
        "        calls action add : actionlib/TwoInts -> adder.add\n    }"
    ) in tsm
    assert "topic " not in tsm  # the five topics are the action, nothing else is left
    assert [d for d in check_models(out, count=False)[1] if d.severity == "error"] == []
    bundle = write_product(out, out / "products" / "adding.yaml", tmp_path / "bundle")
    status, report = smoke_json(bundle)
    assert status == 0 and report["passed"], report["failures"]
    rows = rows_by_interface(report)
    asker = rows["Cloud.asker.add"]
    assert asker["ok"] and asker["topic"] == "/add"
    assert asker["seen"].startswith("result from adder.add (")
    assert "feedback from adder.add (" in asker["seen"]
    served = rows["Cloud.adder.add"]
    assert served["ok"] and served["seen"].startswith("provides action (")
    assert "(0 goals" not in served["seen"]


def test_the_launch_import_with_the_graph_gives_the_same_action(live_graph, tmp_path: Path):
    master, packages, launch = live_graph
    status, _, stderr = import_launch(str(launch), "--package-path", str(packages),
                                      "--graph", master, "-o", str(tmp_path / "line"))  # fmt: skip
    assert status == 0, stderr
    assert stderr == ""
    lines = [line.strip() for line in (tmp_path / "line" / "adding.tsm").read_text().splitlines()]
    assert 'provides action add : actionlib/TwoInts name "/add"' in lines
    assert "calls action add : actionlib/TwoInts -> adder.add" in lines
