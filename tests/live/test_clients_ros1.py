"""The generated ROS 1 writer and reader packages, judged by ROS 1 itself: Debian's
catkin builds and installs them, and the real roslaunch reads the launch files that
start them with their parameters (the store's URL from a launch argument; the token
never in a file). They run against the real service in tests/live/test_smoke_data_path.py."""

from __future__ import annotations

import ast
import shutil
import subprocess
from pathlib import Path

import pytest
import yaml

from spl.generators.clients import generator as clients, runtime as clients_runtime
from spl.generators.ros1 import launch_files as ros1
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list
from spl.smoke.processes import find_ros

from support.service_runtime import write_files

LINE = Path(__file__).resolve().parents[2] / "product_lines" / "data_acquisition"


def product():
    line = load_product_line(LINE)
    return resolve(line, selection_from_list("Positions,Follow,Embedded")).product


RUNTIME = [p.name for p in Path(clients_runtime.__file__).parent.glob("*.py")]
PACKAGES = {
    "position_writer": "writer_node",
    "position_reader": "reader_node",
    "velocity_writer": "writer_node",
    "command_reader": "reader_node",
}


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    """A catkin workspace holding the generated packages, built and installed."""
    root = tmp_path_factory.mktemp("catkin")
    write_files(clients.generate(product()), root)
    (root / "ws").mkdir()
    shutil.copytree(root / "clients" / "ros1", root / "ws" / "src")
    python = find_ros().python
    for goal in ([], ["install"]):
        build = subprocess.run(
            ["catkin_make", "-C", str(root / "ws"), *goal, f"-DPYTHON_EXECUTABLE={python}"],
            cwd=root / "ws",
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert build.returncode == 0, build.stdout[-2000:] + build.stderr[-2000:]
    return root / "ws"


def test_catkin_builds_and_installs_every_generated_package(workspace: Path) -> None:
    installed = workspace / "install"
    for package, module in PACKAGES.items():
        script = installed / "lib" / package / package
        assert script.is_file() and script.stat().st_mode & 0o111, script
        modules = installed / "lib" / "python3" / "dist-packages" / package
        assert {p.name for p in modules.glob("*.py")} == {
            "__init__.py",
            "store_client.py",
            f"{module}.py",
        }
        # the clients' runtime, installed with the node as its subpackage
        assert {p.name for p in (modules / "runtime").glob("*.py")} == set(RUNTIME)
        manifest = (installed / "share" / package / "package.xml").read_text()
        assert '<package format="3">' in manifest and "<exec_depend>rospy</exec_depend>" in manifest


def test_the_nodes_are_rospy_nodes_and_compile_with_the_ros_python(workspace: Path) -> None:
    python = find_ros().python
    sources = sorted((workspace / "src").glob("*/src/*/*.py"))
    assert len(sources) == 3 * len(PACKAGES)
    check = subprocess.run([python, "-m", "py_compile", *map(str, sources)], capture_output=True)
    assert check.returncode == 0, check.stderr
    writer = (workspace / "src/velocity_writer/src/velocity_writer/writer_node.py").read_text()
    imports = {alias.name for n in ast.walk(ast.parse(writer)) if isinstance(n, ast.Import)
               for alias in n.names}  # fmt: skip
    imports |= {n.module for n in ast.walk(ast.parse(writer)) if isinstance(n, ast.ImportFrom)}
    assert {"rospy", "ev3_msgs.msg", "store_client"} <= imports
    assert "rclpy" not in writer
    # the subscribing reader (CommandReader, `subscribe` in the .tsm) carries the WebSocket feed
    reader = (workspace / "src/command_reader/src/command_reader/store_client.py").read_text()
    polling = (workspace / "src/position_reader/src/position_reader/store_client.py").read_text()
    assert "from .runtime.feed import Feed" in reader and ".runtime.feed" not in polling


def test_roslaunch_starts_them_with_the_store_url_argument_and_their_parameters(
    tmp_path: Path,
) -> None:
    resolved = product()
    rover = next(c for c in resolved.system.containers if c.name == "Rover")
    launch = tmp_path / "Rover.launch"
    launch.write_bytes(ros1.launch_file(resolved, rover))
    text = launch.read_text()
    assert 'type="position_writer" name="PositionWriter"' in text
    assert "TOKEN" not in text  # the token comes from the environment, never a file
    roslaunch = find_ros().roslaunch
    dumped = subprocess.run(
        [roslaunch, "--dump-params", str(launch), "position_store_url:=https://cloud.example.org"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert dumped.returncode == 0, dumped.stderr
    params = yaml.safe_load(dumped.stdout)
    assert params["/PositionWriter/store_url"] == "https://cloud.example.org"
    assert params["/PositionWriter/robot_id"] == "rover_1"
    assert params["/PositionWriter/batch_size"] == 100
    assert params["/PositionReader/store_url"] == "https://cloud.example.org"
    assert params["/PositionReader/period"] == 1.0
    default = subprocess.run(
        [roslaunch, "--dump-params", str(launch)], capture_output=True, text=True, timeout=60
    )
    assert yaml.safe_load(default.stdout)["/PositionWriter/store_url"] == "http://localhost:8000"
