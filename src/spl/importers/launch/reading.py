"""Loading the launch files once per combination of argument values, with roslaunch.

roslaunch's loader evaluates one combination at a time (docs/import.md, "How the line
is found"), so the variability is read by loading every combination of the values asked
for and comparing what comes out. The loading happens in ``roslaunch_reader.py``, run
by the Python that has roslaunch (Debian's ``python3-roslaunch``), in one process for
all combinations; this module prepares its request and reads its answer into typed
records.
"""

from __future__ import annotations

import itertools
import json
import os
import re
import shlex
import shutil
import subprocess
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

READER = Path(__file__).with_name("roslaunch_reader.py")
ROS_MISSING = "roslaunch not found: apt-get install ros-core python3-roslaunch"
MAX_BYTES = 1_000_000  # a launch or parameter file longer than this is refused
MAX_COMBINATIONS = 512
_ARG_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_VALUE = re.compile(r"[A-Za-z0-9_.+-]+\Z")


class ImportRefused(Exception):
    """The input is refused as a whole: nothing is written (exit status 1)."""


class RosMissing(ImportRefused):
    """roslaunch is not installed: a program the command cannot do without (exit status
    2, as docs/commands.md says of ``spl smoke``)."""


@dataclass(frozen=True)
class Argument:
    """A launch argument and the values each product may give it, in the order given."""

    name: str
    values: tuple[str, ...]

    @property
    def is_switch(self) -> bool:
        """An argument that is switched on or off: an optional feature, not a group."""
        return sorted(v.lower() for v in self.values) == ["false", "true"]


@dataclass(frozen=True)
class Omission:
    """Something the import could not carry over, where it was written."""

    file: str
    line: int
    message: str

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}: " if self.file else ""
        return f"{where}warning: {self.message}"


@dataclass(frozen=True)
class LoadedNode:
    """A node as roslaunch's loader made it, for one combination."""

    name: str
    namespace: str  # roslaunch's: "/" or "/ns/"
    package: str
    executable: str
    args: tuple[str, ...]  # shlex tokens, as roslaunch passes them to the process
    remaps: tuple[tuple[str, str], ...]
    machine: str
    file: str  # as the warnings show it: relative to the working folder, when under it
    line: int
    source: str  # the file relative to the package path folder holding it, for the .tsm
    unsupported: tuple[str, ...]  # settings no .tsm statement holds (env, respawn, ...)

    @property
    def ros_name(self) -> str:
        return f"{self.namespace.rstrip('/')}/{self.name}"


@dataclass(frozen=True)
class Combination:
    values: tuple[str, ...]  # one per argument, in the order of the --arg options
    nodes: tuple[LoadedNode, ...]
    params: dict[str, Any]
    param_places: dict[str, tuple[str, int]]  # where each parameter was set


def parse_argument(text: str) -> Argument:
    """``NAME=V1,V2,...`` of ``--arg``."""
    name, equals, values = text.partition("=")
    if not equals or not _ARG_NAME.match(name):
        raise ImportRefused(f"--arg {text!r}: expected NAME=V1,V2,... with a launch arg name")
    chosen = tuple(values.split(","))
    bad = [v for v in chosen if not _VALUE.match(v)]
    if bad:
        raise ImportRefused(
            f"--arg {name}: value {bad[0]!r} is not a plain word (letters, digits, _ . + -)"
        )
    if len(set(chosen)) != len(chosen):
        raise ImportRefused(f"--arg {name}: a value is given twice")
    return Argument(name, chosen)


def roslaunch_python() -> str:
    """The interpreter roslaunch runs with (its ``#!`` line): the one that imports it."""
    roslaunch = shutil.which("roslaunch")
    if roslaunch is None:
        raise RosMissing(ROS_MISSING)
    with open(roslaunch, "rb") as stream:
        first = stream.readline().decode("utf-8", "replace")
    words = first[2:].split() if first.startswith("#!") else []
    if words and Path(words[0]).name == "env" and len(words) > 1:
        found = shutil.which(words[1])
        return found if found else ""
    if not words:
        raise RosMissing(ROS_MISSING)
    return words[0]


def load_combinations(
    files: list[Path], arguments: list[Argument], package_path: list[Path]
) -> tuple[list[Combination], list[Omission]]:
    """Every combination of the arguments' values, loaded by roslaunch's loader, and
    what it left out (each warning once, in file and line order)."""
    if len({a.name for a in arguments}) != len(arguments):
        raise ImportRefused("--arg: an argument is given twice")
    combinations = list(itertools.product(*(a.values for a in arguments)))
    if len(combinations) > MAX_COMBINATIONS:
        raise ImportRefused(
            f"{len(combinations)} combinations of --arg values; at most {MAX_COMBINATIONS}"
        )
    roots = sorted(
        {str(p.resolve()) for p in package_path} | {str(f.resolve().parent) for f in files}
    )
    request = {
        "files": [str(f.resolve()) for f in files],
        "combinations": [
            list(zip((a.name for a in arguments), c, strict=True)) for c in combinations
        ],
        "roots": roots,
        "max_bytes": MAX_BYTES,
    }
    environment = {
        "PATH": os.environ.get("PATH", "/usr/bin:/bin"),
        "LANG": "C.UTF-8",
        "ROS_PACKAGE_PATH": os.pathsep.join(str(p.resolve()) for p in package_path),
    }
    python = roslaunch_python()
    try:
        done = subprocess.run(
            [python, "-I", str(READER)], input=json.dumps(request), capture_output=True,
            text=True, env=environment, timeout=600,
        )  # fmt: skip
    except OSError as exc:
        raise RosMissing(f"{ROS_MISSING} ({python}: {exc.strerror})") from None
    except subprocess.TimeoutExpired:
        raise ImportRefused("roslaunch's loader did not answer within 600 s") from None
    if done.returncode != 0 or not done.stdout:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        if "No module named" in last:
            raise RosMissing(f"{ROS_MISSING} ({python}: {last})")
        raise ImportRefused(f"roslaunch's loader failed: {last}")
    answer = json.loads(done.stdout)
    here = str(Path.cwd().resolve()) + os.sep

    def shown(text: str) -> str:
        return text.replace(here, "")

    if "refused" in answer:
        raise ImportRefused(shown(answer["refused"]))
    loaded: list[Combination] = []
    warnings: dict[Omission, None] = {}
    for values, result in zip(combinations, answer["combinations"], strict=True):
        nodes = []
        for raw in result["nodes"]:
            node = _node(raw, shown, [str(p.resolve()) for p in package_path] or roots)
            nodes.append(node)
            for setting in node.unsupported:
                warning = Omission(
                    node.file, node.line, f"node {node.ros_name}: {setting} left out"
                )
                warnings[warning] = None
        for machine in result["machines"]:
            file, number = machine["place"]
            warnings[Omission(shown(file), number, (
                f"machine {machine['name']} ({machine['address']}) left out: a container "
                "says where nodes run (--robot may name the machine)"))] = None  # fmt: skip
        for raw in result["warnings"]:
            message = shown(_one_line(raw["message"]))
            warnings[Omission(shown(raw["file"]), raw["line"], message)] = None
        places = {k: (f, n) for k, (f, n) in result["param_lines"].items()}
        loaded.append(Combination(tuple(values), tuple(nodes), result["params"], places))
    return loaded, sorted(warnings, key=lambda w: (w.file, w.line, w.message))


def _relative(path: str, roots: list[str]) -> str:
    """``path`` under the deepest package path folder holding it (else its name)."""
    holding = [r for r in roots if path.startswith(r.rstrip(os.sep) + os.sep)]
    if not holding:
        return Path(path).name
    return path[len(max(holding, key=len).rstrip(os.sep)) + 1 :]


def _one_line(message: str) -> str:
    """A warning on one line, blanks collapsed (roslaunch's messages run over lines)."""
    return " ".join(message.split())


def _node(raw: dict[str, Any], shown: Callable[[str], str], roots: list[str]) -> LoadedNode:
    try:
        args = tuple(shlex.split(raw["args"]))
    except ValueError:
        args = (raw["args"],)
    unsupported = [f"env {name}={value}" for name, value in raw["env"]]
    if raw["respawn"]:
        unsupported.append("respawn")
    if raw["launch_prefix"]:
        unsupported.append(f"launch-prefix {raw['launch_prefix']!r}")
    if raw["cwd"]:
        unsupported.append(f"cwd {raw['cwd']}")
    return LoadedNode(
        name=raw["name"], namespace=raw["namespace"], package=raw["package"],
        executable=raw["type"], args=args,
        remaps=tuple((source, target) for source, target in raw["remaps"]),
        machine=raw["machine"], file=shown(raw["file"]), line=raw["line"],
        source=_relative(raw["file"], roots),
        unsupported=tuple(unsupported),
    )  # fmt: skip
