"""``spl import graph`` against a master that answers what it likes: a real XML-RPC
server on 127.0.0.1 speaking the ROS master API. Names that are no valid ROS names are
left out, reported; an answer of the wrong shape is refused in one line, exit 1,
nothing written. (The live graph of a real roscore: tests/live/test_import_graph.py.)
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from pathlib import Path
from xmlrpc.server import SimpleXMLRPCServer

import pytest
from click.testing import CliRunner

from spl.cli import main


class Master:
    """A stand-in ROS master answering ``state`` to getSystemState."""

    def __init__(self, state: object) -> None:
        self.state = state

    def getSystemState(self, caller: str) -> list:
        return [1, "state", self.state]

    def getTopicTypes(self, caller: str) -> list:
        return [1, "types", [["/chatter", "std_msgs/String"]]]

    def lookupNode(self, caller: str, name: str) -> list:
        return [-1, f"unknown node {name}", ""]


@pytest.fixture
def master() -> Iterator[Master]:
    answers = Master([[], [], []])
    server = SimpleXMLRPCServer(("127.0.0.1", 0), logRequests=False, allow_none=True)
    server.register_instance(answers)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    answers.uri = f"http://127.0.0.1:{server.server_address[1]}/"  # type: ignore[attr-defined]
    yield answers
    server.shutdown()
    server.server_close()


def run(master: Master, out: Path):
    return CliRunner().invoke(main, ["import", "graph", "-o", str(out), "--master", master.uri])


def test_names_that_are_no_ros_names_are_left_out_reported(master, tmp_path):
    master.state = [
        [["/chatter", ["/talker", "/bad name"]], ["/bad topic\n", ["/talker"]]],
        [["/rosout", ["/talker"]]],
        [],
    ]
    result = run(master, tmp_path / "weird")
    assert result.exit_code == 0, result.stderr
    lines = result.stderr.splitlines()
    assert "warning: node '/bad name' left out: not a valid global ROS name" in lines
    assert "warning: topic '/bad topic\\n' left out: not a valid global ROS name" in lines
    # /talker runs no process this machine can see: it cannot be launched by a bundle
    assert lines[-1].startswith("warning: node /talker left out: its package is not known")
    assert "1 product, 0 nodes" in result.stdout


@pytest.mark.parametrize(
    "state", [[1, 2], "state", [[["/chatter", "/talker"]], [], []], [[["/chatter"]], [], []]]
)
def test_an_answer_of_the_wrong_shape_is_refused(master, tmp_path, state):
    master.state = state
    result = run(master, tmp_path / "line")
    assert result.exit_code == 1
    assert result.stderr.startswith("error: ")
    assert len(result.stderr.splitlines()) == 1
    assert not (tmp_path / "line").exists()
