"""The round trip of ``spl import launch``: original launch files and the launch files of
the imported products, both loaded by roslaunch's own loader and compared.

Both sides go through ``roslaunch_dump.py`` (roslaunch's ``XmlLoader`` under the
Python that has roslaunch), in one process for all jobs. The original side gets what a
user of the original files has: the ``TURTLEBOT3_MODEL`` variable their defaults read,
and a package ``xacro`` on the package path (an empty one: the ``<param command>`` it
would run is never run, its value is a marker).
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path
from typing import Any

from click.testing import CliRunner

from spl.cli import main
from spl.generators.ros1.launch_files import generate
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file

ROOT = Path(__file__).resolve().parents[2]
TURTLEBOT3 = ROOT / "tests" / "data" / "ros1-launch" / "turtlebot3"
DUMP = Path(__file__).with_name("roslaunch_dump.py")
PACKAGE_XML = (
    '<package format="2"><name>{}</name><version>0.0.0</version><description>stub'
    '</description><maintainer email="a@example.org">a</maintainer><license>none</license>'
    "</package>"
)


def ros_python() -> str:
    """The interpreter roslaunch runs with."""
    roslaunch = shutil.which("roslaunch")
    assert roslaunch, "ROS 1 (roslaunch) is needed by these tests"
    first = Path(roslaunch).read_text().splitlines()[0]
    words = first[2:].split()
    return shutil.which(words[1]) or "" if Path(words[0]).name == "env" else words[0]


def stub_packages(folder: Path, *names: str) -> Path:
    """A package folder holding empty packages ``names``."""
    for name in names:
        (folder / name).mkdir(parents=True, exist_ok=True)
        (folder / name / "package.xml").write_text(PACKAGE_XML.format(name))
    return folder


def import_launch(*args: str) -> tuple[int, str, str]:
    """``spl import launch ARGS``: exit status, stdout, stderr."""
    result = CliRunner().invoke(main, ["import", "launch", *args])
    return result.exit_code, result.stdout, result.stderr


def product_launch_files(line: Path, product: Path, out: Path) -> list[Path]:
    """The ROS 1 launch files ``spl resolve`` writes for the product file ``product``."""
    resolved = resolve(load_product_line(line), load_selection_file(product)).product
    written = []
    for name, data in sorted(generate(resolved).items()):
        target = out / name
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(data)
        written.append(target)
    return written


def load_with_roslaunch(jobs: list[dict[str, Any]], package_path: list[Path]) -> list[dict]:
    """What roslaunch's loader makes of each job (``roslaunch_dump.py``)."""
    done = subprocess.run(
        [ros_python(), "-I", str(DUMP)],
        input=json.dumps(jobs),
        capture_output=True,
        text=True,
        env={"PATH": "/usr/bin:/bin", "ROS_PACKAGE_PATH": ":".join(map(str, package_path))},
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def differences(original: dict, imported: dict) -> set[tuple[str, str]]:
    """``(node or parameter, what differs)`` between two loadings: a node's package,
    type, namespace or command line (args, then remappings as ``from:=to``), a node or
    parameter only one side has, or a parameter's value (its Python type included)."""
    found = set()
    for name in original["nodes"].keys() | imported["nodes"].keys():
        if name not in original["nodes"] or name not in imported["nodes"]:
            found.add((name, "node"))
            continue
        for field, value in original["nodes"][name].items():
            if imported["nodes"][name][field] != value:
                found.add((name, field))
    before, after = original["params"], imported["params"]
    for key in before.keys() | after.keys():
        if key not in before or key not in after:
            found.add((key, "param"))
        elif before[key] != after[key] or _types(before[key]) != _types(after[key]):
            found.add((key, "value"))
    return found


def _types(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _types(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_types(v) for v in value]
    return type(value).__name__
