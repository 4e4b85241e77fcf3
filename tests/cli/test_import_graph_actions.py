"""``spl import graph`` of the topics actionlib makes of an action (docs/import.md, "A
live graph"), against a real XML-RPC server on 127.0.0.1 answering as a ROS master
whose graph the test writes: a whole group of the five topics becomes ``provides
action`` on its server and ``calls action`` on each client, which the import's own
``spl check`` passes; a partial group stays topics with a note naming the group and why.
(A real roscore with actionlib's own server and client: tests/live/test_import_graph.py.)

The nodes run a real process (a script of a package of ``--package-path``, waiting on
its stdin) whose pid the master gives, so that the import finds their implementation.
"""

from __future__ import annotations

import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from xmlrpc.server import SimpleXMLRPCServer

import pytest
from click.testing import CliRunner

from spl.cli import main

from support.launch_round_trip import stub_packages

TYPES = {
    "/fib/goal": "actionlib/TwoIntsActionGoal",
    "/fib/cancel": "actionlib_msgs/GoalID",
    "/fib/status": "actionlib_msgs/GoalStatusArray",
    "/fib/feedback": "actionlib/TwoIntsActionFeedback",
    "/fib/result": "actionlib/TwoIntsActionResult",
    "/chatter": "std_msgs/String",
}
SERVER_SENDS, CLIENT_SENDS = ("status", "feedback", "result"), ("goal", "cancel")


def state(servers: tuple[str, ...] = ("/fib_server",), clients: tuple[str, ...] = ("/fib_client",),
          leave_out: tuple[str, ...] = ()) -> list:  # fmt: skip
    """getSystemState of actionlib servers and clients on /fib (``leave_out``: topics
    nobody uses), and a talker on /chatter that /fib_server listens to."""
    publishers: dict[str, list[str]] = {"/chatter": ["/talker"]}
    subscribers: dict[str, list[str]] = {"/chatter": ["/fib_server"]}
    for part in (*SERVER_SENDS, *CLIENT_SENDS):
        topic = f"/fib/{part}"
        if topic not in leave_out:
            sends, takes = (servers, clients) if part in SERVER_SENDS else (clients, servers)
            publishers.setdefault(topic, []).extend(sends)
            subscribers.setdefault(topic, []).extend(takes)
    return [sorted(publishers.items()), sorted(subscribers.items()), []]


class Master:
    """A ROS master answering with ``self.state`` and ``self.types``; every node it
    knows but those in ``self.unknown`` is the process ``self.pid``."""

    def __init__(self) -> None:
        self.state, self.types, self.unknown = state(), dict(TYPES), set[str]()
        self.uri, self.pid = "", 0

    def getSystemState(self, caller: str) -> list:
        return [1, "state", self.state]

    def getTopicTypes(self, caller: str) -> list:
        return [1, "types", sorted(self.types.items())]

    def lookupNode(self, caller: str, name: str) -> list:
        if name in self.unknown:
            return [-1, f"unknown node {name}", ""]
        return [1, "node", self.uri]  # the node's API is this server too

    def getPid(self, caller: str) -> list:
        return [1, "pid", self.pid]


@pytest.fixture(scope="module")
def packages(tmp_path_factory) -> Path:
    folder = stub_packages(tmp_path_factory.mktemp("packages"), "fib_demo")
    (folder / "fib_demo" / "scripts").mkdir()
    (folder / "fib_demo" / "scripts" / "node.py").write_text("import sys\nsys.stdin.read()\n")
    return folder


@pytest.fixture(scope="module")
def node_process(packages) -> Iterator[int]:
    script = packages / "fib_demo" / "scripts" / "node.py"
    process = subprocess.Popen([sys.executable, str(script)], stdin=subprocess.PIPE)
    yield process.pid
    assert process.stdin is not None
    process.stdin.close()
    process.wait(timeout=60)


@pytest.fixture
def master(node_process) -> Iterator[Master]:
    answers = Master()
    server = SimpleXMLRPCServer(("127.0.0.1", 0), logRequests=False, allow_none=True)
    server.register_instance(answers)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    answers.uri = f"http://127.0.0.1:{server.server_address[1]}/"
    answers.pid = node_process
    yield answers
    server.shutdown()
    server.server_close()


def run(master: Master, out: Path, packages: Path, *options: str):
    return CliRunner().invoke(main, ["import", "graph", "-o", str(out), "--master", master.uri,
                                     "--package-path", str(packages), *options])  # fmt: skip


def test_a_whole_group_is_one_action_served_and_called(master, packages, tmp_path):
    master.state = state(clients=("/fib_client", "/other_client"))
    result = run(master, tmp_path / "fib", packages)
    assert result.exit_code == 0, result.stderr  # the import checks the line it writes
    assert result.stderr == ""
    tsm = (tmp_path / "fib" / "fib.tsm").read_text()
    assert "node fib_server {\n        implementation fib_demo/node.py\n" in tsm
    assert 'provides action fib : actionlib/TwoInts name "/fib"' in tsm
    for client in ("fib_client", "other_client"):
        block = tsm.split(f"node {client} {{")[1].split("}")[0]
        assert block.endswith("calls action fib : actionlib/TwoInts -> fib_server.fib\n    ")
    # none of the five topics is left as a topic; the others stay
    assert "topic fib" not in tsm and "/fib/" not in tsm
    assert "subscribes chatter <- chatter" in tsm.split("node fib_server")[1]


def test_a_client_on_the_robot_is_bridged_to_its_server(master, packages, tmp_path):
    result = run(master, tmp_path / "fib", packages, "--robot", "fib_client")
    assert result.exit_code == 0, result.stderr
    tsm = (tmp_path / "fib" / "fib.tsm").read_text()
    assert "calls action fib : actionlib/TwoInts\n" in tsm.split("node fib_client")[1]
    assert tsm.endswith("\nbridge Robot.fib_client.fib -> Cloud.fib_server.fib\n")


def test_a_client_whose_server_is_left_out_names_it_as_external(master, packages, tmp_path):
    master.unknown = {"/fib_server"}
    result = run(master, tmp_path / "fib", packages)
    assert result.exit_code == 0, result.stderr
    assert result.stderr.startswith("warning: node /fib_server left out: its package is not known")
    tsm = (tmp_path / "fib" / "fib.tsm").read_text()
    assert (
        'calls action fib : actionlib/TwoInts external "served by /fib_server, which is not in '
        'the line"'
    ) in tsm


@pytest.mark.parametrize(
    ("graph", "types", "why"),
    [
        (state(leave_out=("/fib/result",)), {}, "/fib/result is missing"),
        (state(), {"/fib/feedback": "actionlib/TwoIntsFeedback"},
         "/fib/feedback is actionlib/TwoIntsFeedback, not actionlib/TwoIntsActionFeedback"),
        (state(), {"/fib/goal": "actionlib/OtherActionGoal"},
         "/fib/feedback is actionlib/TwoIntsActionFeedback, not actionlib/OtherActionFeedback"),
        (state(servers=("/fib_server", "/fib_server_2")), {},
         "nodes /fib_server, /fib_server_2 all serve it"),
        (state(servers=()), {},
         "no node serves it (subscribes goal and cancel, publishes status, feedback "
         "and result)"),
        ([*state()[:1], [*state()[1], ["/fib/feedback", ["/monitor"]]], []], {},
         "node /monitor publishes or subscribes only some of its topics, as neither an "
         "actionlib server nor a client does"),
    ],
    ids=["topic missing", "type not an action's", "types of two actions", "two servers",
         "no server", "a node using some"],
)  # fmt: skip
def test_a_partial_group_stays_topics_with_a_note_saying_why(
    master, packages, tmp_path, graph, types, why
):
    master.state = graph
    master.types |= types
    result = run(master, tmp_path / "fib", packages)
    assert result.exit_code == 0, result.stderr
    note = f"warning: action /fib imported as its topics: {why}"
    assert note in result.stderr.splitlines()
    assert note in (tmp_path / "fib" / "import-report.txt").read_text().splitlines()
    tsm = (tmp_path / "fib" / "fib.tsm").read_text()
    assert "provides action" not in tsm and "calls action" not in tsm
    assert 'name "/fib/goal"' in tsm  # the topics are there, as the graph has them
