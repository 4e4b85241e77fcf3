"""``spl import graph`` from a live ROS 1 graph: a real roscore and rospy nodes the test
starts with roslaunch (a talker, a listener, a node serving a service and listening
too), read through the master's API into a line that ``spl check`` passes, that
resolves, and whose product ``spl smoke`` brings up green with the real ROS 1; and
``spl import launch --graph`` of the same launch file gives the same topics.
"""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

from spl.pipeline import check_models
from spl.smoke.processes import free_port

from support.launch_round_trip import import_launch, stub_packages
from support.live_master import launched, system_state, wait_for, write_nodes
from support.smoke_runs import smoke_json, spl_command, write_product

NODES = {
    "talker.py": """import rospy
from std_msgs.msg import String
rospy.init_node("talker")
pub = rospy.Publisher("chatter", String, queue_size=10)
rate = rospy.Rate(5)
while not rospy.is_shutdown():
    pub.publish(String("hello"))
    rate.sleep()
""",
    "listener.py": """import rospy
from std_msgs.msg import String
rospy.init_node("listener")
rospy.Subscriber("chatter", String, lambda message: None)
rospy.spin()
""",
    "resetter.py": """import rospy
from roscpp.srv import Empty, EmptyResponse
from std_msgs.msg import String
rospy.init_node("resetter")
rospy.Service("reset", Empty, lambda request: EmptyResponse())
rospy.Subscriber("chatter", String, lambda message: None)
rospy.spin()
""",
}
EXPECTED = {"/talker", "/listener", "/resetter"}
LAUNCH = """<launch>
  <node pkg="chatter_demo" type="talker.py" name="talker"/>
  <node pkg="chatter_demo" type="listener.py" name="listener"/>
  <node pkg="chatter_demo" type="resetter.py" name="resetter"><param name="rate" value="5"/></node>
</launch>
"""


def graph_state(master: str) -> tuple[set[str], set[str]] | None:
    """The nodes publishing or subscribing, and the services, or None while there is
    no master."""
    state = system_state(master)
    if state is None:
        return None
    pubs, subs, srvs = state
    nodes = {n for _, names in pubs + subs for n in names}
    return nodes, {s for s, _ in srvs}


@pytest.fixture(scope="module")
def live_graph(tmp_path_factory):
    folder = tmp_path_factory.mktemp("graph")
    packages = stub_packages(folder / "packages", "chatter_demo")
    write_nodes(packages / "chatter_demo" / "scripts", NODES)
    (packages / "chatter_demo" / "launch").mkdir()
    launch = packages / "chatter_demo" / "launch" / "chatter.launch"
    launch.write_text(LAUNCH)
    with launched(folder, packages, launch) as master:

        def registered() -> bool:
            state = graph_state(master)
            return state is not None and state[0] >= EXPECTED and "/reset" in state[1]

        wait_for("the nodes", registered)
        yield master, packages, launch


def run(*args: str, master: str) -> subprocess.CompletedProcess:
    return subprocess.run([*spl_command(), "import", "graph", *args], capture_output=True,
                          text=True, env={**os.environ, "ROS_MASTER_URI": master},
                          timeout=300)  # fmt: skip


def test_a_live_graph_imports_resolves_and_smokes_green(live_graph, tmp_path):
    master, packages, _ = live_graph
    out = tmp_path / "chatter"
    done = run("-o", str(out), "--package-path", str(packages), master=master)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("imported chatter: 1 product, 3 nodes, 0 things")
    tsm = (out / "chatter.tsm").read_text()
    for line in [
        'topic chatter : std_msgs/String name "/chatter"',
        "node talker {\n        implementation chatter_demo/talker.py\n"
        "        publishes chatter -> chatter\n    }",
        "node listener {\n        implementation chatter_demo/listener.py\n"
        "        subscribes chatter <- chatter\n    }",
        'provides reset : roscpp/Empty name "/reset"',
    ]:
        assert line in tsm
    assert [d for d in check_models(out, count=False)[1] if d.severity == "error"] == []
    bundle = write_product(out, out / "products" / "chatter.yaml", tmp_path / "bundle")
    status, report = smoke_json(bundle)
    assert status == 0 and report["passed"], report["failures"]


def test_without_the_package_path_nodes_are_left_out_reported(live_graph, tmp_path):
    master, _, _ = live_graph
    done = run("-o", str(tmp_path / "line"), master=master)
    assert done.returncode == 0, done.stderr
    lines = done.stderr.splitlines()
    assert len(lines) == 3
    assert all(" left out: its package is not known" in line for line in lines)


def test_no_master_is_one_line_and_nothing_written(tmp_path):
    master = f"http://127.0.0.1:{free_port()}/"
    done = run("-o", str(tmp_path / "line"), master=master)
    assert done.returncode == 1
    assert done.stderr.startswith(f"error: {master}: getSystemState failed: ")
    assert len(done.stderr.splitlines()) == 1
    assert not (tmp_path / "line").exists()


def test_the_launch_import_with_the_graph_gives_the_same_topics(live_graph, tmp_path):
    master, packages, launch = live_graph
    from_graph, from_launch = tmp_path / "graph", tmp_path / "launch"
    done = run("-o", str(from_graph), "--package-path", str(packages), master=master)
    assert done.returncode == 0, done.stderr
    status, _, stderr = import_launch(str(launch), "--package-path", str(packages),
                                      "--graph", master, "-o", str(from_launch))  # fmt: skip
    assert status == 0, stderr
    assert stderr == ""

    def statements(path: Path, start: str) -> list[str]:
        text = path.read_text()
        return [line.strip() for line in text.splitlines() if line.strip().startswith(start)]

    graph_tsm, launch_tsm = from_graph / "graph.tsm", from_launch / "chatter.tsm"
    assert statements(launch_tsm, "topic ") == statements(graph_tsm, "topic ") != []
    for verb in ("publishes ", "subscribes ", "provides "):
        assert statements(launch_tsm, verb) == statements(graph_tsm, verb)
    assert "param rate : int = 5" in launch_tsm.read_text()  # and what the launch file says
    assert [d for d in check_models(from_launch, count=False)[1] if d.severity == "error"] == []
