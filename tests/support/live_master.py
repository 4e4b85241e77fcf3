"""A ROS 1 graph started for a test: stub nodes of a package, launched by roslaunch on a
roscore of their own (a free port, a ROS_HOME in the test's folder), and everything
started ended after, leaving no process (tests/live/test_import_graph*.py)."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import time
import uuid
import xmlrpc.client
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from spl.smoke.processes import free_port

from support.launch_round_trip import ros_python
from support.smoke_runs import TAG, leftovers


def write_nodes(scripts: Path, nodes: dict[str, str]) -> None:
    """Each node's script, run by the Python that has rospy and actionlib."""
    scripts.mkdir(parents=True)
    for name, text in nodes.items():
        (scripts / name).write_text(f"#!{ros_python()}\n{text}")
        (scripts / name).chmod(0o755)


def system_state(master: str) -> Any:
    """The master's publishers, subscribers and services, or None while there is none."""
    try:
        return xmlrpc.client.ServerProxy(master).getSystemState("/test")[2]
    except OSError:
        return None


def wait_for(what: str, ready: Callable[[], bool], deadline: float = 120.0) -> None:
    """Polls ``ready()`` until it holds; fails after ``deadline`` seconds."""
    end = time.monotonic() + deadline
    while not ready():
        assert time.monotonic() < end, f"{what} not ready after {deadline} s"
        time.sleep(0.2)


@contextlib.contextmanager
def launched(folder: Path, packages: Path, launch: Path) -> Iterator[str]:
    """The master's URI, with ``launch`` running on it; ended on leaving (roscore ends
    its rosmaster and rosout on SIGINT: nothing of the graph is left)."""
    port = free_port()
    master = f"http://127.0.0.1:{port}/"
    tag = uuid.uuid4().hex
    env = {**os.environ, "ROS_MASTER_URI": master, "ROS_HOME": str(folder / "ros"), TAG: tag,
           "ROS_PACKAGE_PATH": str(packages)}  # fmt: skip

    def start(*argv: str) -> subprocess.Popen[bytes]:
        return subprocess.Popen(argv, env=env, cwd=folder, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)  # fmt: skip

    started = [start("roscore", "-p", str(port))]
    try:
        wait_for("roscore", lambda: system_state(master) is not None)
        started.append(start("roslaunch", "--wait", str(launch)))
        yield master
    finally:
        for process in reversed(started):
            process.send_signal(signal.SIGINT)
        for process in started:
            try:
                process.wait(timeout=60)
            except subprocess.TimeoutExpired:
                process.kill()
        assert leftovers(tag, wait=30) == []
