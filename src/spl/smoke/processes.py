"""The processes of a smoke rehearsal: finding ROS 1, starting, and always cleaning up.

Every process a rehearsal starts gets a private marker in its environment
(``SPL_SMOKE_RUN=<random token>``), which roslaunch, roscore and the stand-ins pass on
to everything they start. That matters because roslaunch puts each node (and roscore
its ``rosmaster`` and ``rosout``) in a session of its own, so killing the process
groups we started does not reach them; sweeping ``/proc`` for the marker does, and
kills exactly the processes of this run and nothing else on the machine. The direct
children also get ``PR_SET_PDEATHSIG``: if spl itself is killed outright, roscore and
roslaunch are told to shut down their nodes.

Executables are substituted without touching the bundle's launch files: a sandbox
catkin workspace maps every ``pkg``/``type`` the launch files name to a wrapper that
runs the stand-in (see :func:`write_sandbox`).
"""

from __future__ import annotations

import contextlib
import os
import re
import shlex
import shutil
import signal
import socket
import subprocess
import time
import uuid
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from spl.core.lifetime import die_with_parent

MARKER = "SPL_SMOKE_RUN"
ROS_MISSING = (
    "roscore not found: apt-get install ros-core python3-rospy python3-roslaunch python3-rostopic"
)
ACTIONLIB_MISSING = "apt-get install python3-actionlib"
STANDIN = Path(__file__).with_name("standin.py")
# What the caller's environment may say about a ROS graph; none of it reaches a rehearsal.
CALLER_ROS_VARIABLES = (
    "ROS_MASTER_URI",
    "ROS_NAMESPACE",
    "ROS_HOSTNAME",
    "ROS_IP",
    "ROS_HOME",
    "ROS_LOG_DIR",
    "ROS_PACKAGE_PATH",
    "CMAKE_PREFIX_PATH",
)
ANSI_ESCAPE = re.compile(r"\x1b\[[0-9;]*[A-Za-z]|\x1b\][^\x07]*\x07")
SAFE_FILE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.\-]*\Z")


class RosMissing(Exception):
    """ROS 1 is not installed (exit status 2 on the command line)."""


@dataclass(frozen=True)
class RosInstall:
    roscore: str
    roslaunch: str
    python: str  # the interpreter that has rospy: the one roslaunch runs with


def find_ros() -> RosInstall:
    """roscore, roslaunch and the Python they run with (read from roslaunch's ``#!``
    line), checked to import rospy and genpy."""
    roscore, roslaunch = shutil.which("roscore"), shutil.which("roslaunch")
    if not roscore or not roslaunch:
        raise RosMissing(ROS_MISSING)
    python = _interpreter(Path(roslaunch))
    check = [python or "", "-I", "-c", "import rospy, genpy.dynamic"]  # (run with one)
    if not python or subprocess.run(check, capture_output=True).returncode != 0:
        raise RosMissing(f"rospy not importable by {python or 'roslaunch'}: {ROS_MISSING}")
    return RosInstall(roscore, roslaunch, python)


def actionlib_missing(python: str) -> str | None:
    """Why the stand-ins cannot play actions with ``python`` (the Python that has rospy),
    or None when its actionlib imports (Debian's ``python3-actionlib``)."""
    check = [python, "-I", "-c", "import actionlib, actionlib_msgs.msg"]
    if subprocess.run(check, capture_output=True).returncode == 0:
        return None
    return f"actionlib not importable by {python}: {ACTIONLIB_MISSING}"


def _interpreter(script: Path) -> str | None:
    try:
        with script.open("rb") as stream:
            first = stream.readline().decode("utf-8", "replace")
    except OSError:
        return None
    words = first[2:].split() if first.startswith("#!") else []
    if words and Path(words[0]).name == "env" and len(words) > 1:
        return shutil.which(words[1])
    return words[0] if words else None


def free_port() -> int:
    """A TCP port free on the loopback interface right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def standin_command(python: str) -> str:
    """The wrapper line that runs a stand-in node with the Python that has rospy."""
    return f'exec {shlex.quote(python)} -I {shlex.quote(str(STANDIN))} node "$@"'


def script_command(python: str, script: Path, paths: list[Path]) -> str:
    """The wrapper line that runs a node's own script with ``paths`` importable."""
    pythonpath = shlex.quote(":".join(str(p) for p in paths))
    return f'PYTHONPATH={pythonpath} exec {shlex.quote(python)} {shlex.quote(str(script))} "$@"'


def write_sandbox(root: Path, executables: Iterable[tuple[str, str, str]]) -> None:
    """A catkin workspace in which roslaunch finds every ``(package, type)`` as a
    wrapper running the given shell ``command`` (the stand-in, or a generated node's own
    script).

    roslaunch resolves ``<node pkg type>`` with ``roslib.packages.find_node``: the first
    catkin workspace of ``CMAKE_PREFIX_PATH`` (a folder with a ``.catkin`` file) that
    has ``lib/<pkg>``, else the package folder rospack finds on ``ROS_PACKAGE_PATH``.
    Pointing both at this folder makes the stand-in win even over an installed package
    of the same name, while the launch file itself stays the bundle's own, so the node
    name, namespace, remappings, parameters and arguments come from it unchanged.

    Why not the alternatives: a ``launch-prefix`` is put in front of the executable
    roslaunch has already found, so it cannot stand in for a package that is not
    installed (and a prefixed copy of the launch file would no longer be the bundle's
    file); a custom process launcher through roslaunch's Python API would replace the
    real ``roslaunch`` command by its internal classes. Here the real command runs the
    real file; only the package lookup answers with the stand-in.
    """
    root.mkdir(parents=True, exist_ok=True)
    (root / ".catkin").write_text("", encoding="utf-8")
    for package, executable, command in sorted(set(executables)):
        if not SAFE_FILE_NAME.match(package) or not SAFE_FILE_NAME.match(executable):
            continue  # roslaunch will report the node it cannot find
        share = root / "share" / package
        share.mkdir(parents=True, exist_ok=True)
        (share / "package.xml").write_text(
            f'<package format="2"><name>{package}</name><version>0.0.0</version>'
            "<description>spl smoke stand-in</description>"
            '<maintainer email="smoke@localhost">spl</maintainer>'
            "<license>Apache-2.0</license></package>\n",
            encoding="utf-8",
        )
        wrapper = root / "lib" / package / executable
        wrapper.parent.mkdir(parents=True, exist_ok=True)
        wrapper.write_text(f"#!/bin/sh\n{command}\n", encoding="utf-8")
        wrapper.chmod(0o755)


class Processes:
    """The processes of one rehearsal; leaving the ``with`` block ends all of them."""

    def __init__(self, run_dir: Path) -> None:
        self.run_dir = run_dir
        self.token = uuid.uuid4().hex
        self.children: list[tuple[str, subprocess.Popen[bytes], Path]] = []
        self.retired: set[int] = set()

    def environment(self, **settings: str) -> dict[str, str]:
        """The caller's environment without its ROS graph settings, with the marker."""
        env = {k: v for k, v in os.environ.items() if k not in CALLER_ROS_VARIABLES}
        env[MARKER] = self.token
        env.update(settings)
        return env

    def start(self, label: str, argv: list[str], env: dict[str, str]) -> subprocess.Popen[bytes]:
        log = self.run_dir / "logs" / f"{len(self.children):02d}-{label}.log"
        log.parent.mkdir(parents=True, exist_ok=True)
        with log.open("wb") as output:
            process = subprocess.Popen(
                argv, env=env, stdin=subprocess.DEVNULL, stdout=output,
                stderr=subprocess.STDOUT, start_new_session=True, preexec_fn=die_with_parent,
            )  # fmt: skip
        self.children.append((label, process, log))
        return process

    def retire(self, process: subprocess.Popen[bytes]) -> None:
        """A child that was replaced: stopped if still running, no longer reported by
        :meth:`exited` (its own children are still swept by :meth:`stop`)."""
        with contextlib.suppress(ProcessLookupError):
            process.terminate()
        self.retired.add(process.pid)

    def output(self, label: str) -> str:
        """Everything the child ``label`` has written so far, colours removed."""
        for name, _, log in self.children:
            if name == label:
                return ANSI_ESCAPE.sub("", log.read_text(encoding="utf-8", errors="replace"))
        return ""

    def exited(self) -> list[tuple[str, int, str]]:
        """``(label, exit status, last lines of its output)`` of children that ended."""
        ended = []
        for label, process, log in self.children:
            if process.poll() is not None and process.pid not in self.retired:
                ended.append((label, process.returncode, tail(log)))
        return ended

    def stop(self) -> None:
        """SIGTERM every process of the run, SIGKILL what is left after a second, wait
        until none remains (each one is checked, not assumed). Neither a second Ctrl-C
        nor a SIGTERM can interrupt this."""
        previous = {}
        for number in (signal.SIGINT, signal.SIGTERM):
            with contextlib.suppress(ValueError):  # not the main thread: no signals here
                previous[number] = signal.signal(number, signal.SIG_IGN)
        try:
            self._stop()
        finally:
            for number, handler in previous.items():
                signal.signal(number, handler)

    def _stop(self) -> None:
        deadline = time.monotonic() + 1.0
        signalled: set[int] = set()
        while True:
            alive = marked_processes(self.token)
            for _, process, _ in self.children:
                process.poll()
            if not alive:
                break
            late = time.monotonic() > deadline
            for pid in alive:
                if late or pid not in signalled:
                    with contextlib.suppress(ProcessLookupError, PermissionError):
                        os.kill(pid, signal.SIGKILL if late else signal.SIGTERM)
                    signalled.add(pid)
            if time.monotonic() > deadline + 5.0:
                break  # only zombies of other parents can remain; nothing runs any more
            time.sleep(0.05)
        for _, process, _ in self.children:
            with contextlib.suppress(subprocess.TimeoutExpired):
                process.wait(timeout=1.0)

    def __enter__(self) -> Processes:
        return self

    def __exit__(self, *_: object) -> None:
        self.stop()


def marked_processes(token: str) -> list[int]:
    """Pids of the running (not zombie) processes whose environment carries ``token``."""
    needle = f"{MARKER}={token}".encode() + b"\0"
    found = []
    for entry in os.scandir("/proc"):
        if not entry.name.isdigit():
            continue
        try:
            with open(f"/proc/{entry.name}/environ", "rb") as stream:
                environ = stream.read() + b"\0"
            if needle not in environ:
                continue
            with open(f"/proc/{entry.name}/stat", "rb") as stream:
                state = stream.read().rsplit(b")", 1)[1].split()[0]
        except (OSError, IndexError):
            continue
        if state not in (b"Z", b"X"):
            found.append(int(entry.name))
    return found


def tail(path: Path, lines: int = 5) -> str:
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return ""
    text = ANSI_ESCAPE.sub("", text)  # roslaunch colours its output
    return "\n".join(line for line in text.strip().splitlines()[-lines:] if line.strip())


def write_messages(root: Path, messages: dict[str, str]) -> None:
    """Python message packages for the generated nodes (``from rover_msgs.msg import
    PositionInSecond``): each class is made at import by genpy from the plan's
    definition, as the stand-ins make theirs, so both sides agree on the md5sum."""
    packages: dict[str, dict[str, str]] = {}
    for type_name, definition in messages.items():
        package, _, name = type_name.partition("/")
        if SAFE_FILE_NAME.match(package) and name.isidentifier():
            packages.setdefault(package, {})[name] = definition
    for package, definitions in packages.items():
        folder = root / package / "msg"
        folder.mkdir(parents=True, exist_ok=True)
        (root / package / "__init__.py").write_text("", encoding="utf-8")
        (folder / "__init__.py").write_text(
            "import genpy.dynamic\n\n"
            f"DEFINITIONS = {definitions!r}\n"
            "for _name, _text in DEFINITIONS.items():\n"
            f"    _type = {package!r} + '/' + _name\n"
            "    globals()[_name] = genpy.dynamic.generate_dynamic(_type, _text)[_type]\n",
            encoding="utf-8",
        )
