"""The generated writer/reader ROS 2 packages: ament_python layout, entry points, the
rclpy nodes compile (rclpy itself cannot be installed here), names stay safe."""

from __future__ import annotations

import ast
import py_compile
from pathlib import Path

import pytest
from lxml import etree

from spl.core.diagnostics import ModelError
from spl.generators.clients import generator as clients
from spl.resolver.resolution.data_clients import client_package_name

from support.service_models import product
from support.service_runtime import write_files

EXPECTED = {
    "position_writer": ("writer_node", "rover_msgs", "PositionInSecond"),
    "position_reader": ("reader_node", "rover_msgs", "PositionInDEG"),
    "velocity_writer": ("writer_node", "ev3_msgs", "Velocity"),
    "command_reader": ("reader_node", "ev3_msgs", "Command"),
}


@pytest.fixture(scope="module")
def files() -> dict[str, bytes]:
    return clients.generate(product())


def test_client_package_names() -> None:
    assert client_package_name("PositionWriter") == "position_writer"
    assert client_package_name("EV3Reader") == "ev3_reader"
    assert client_package_name("commandReader2") == "command_reader2"
    # were "import" and "global": `from import.reader_node import main` does not parse
    assert client_package_name("Import") == "import_client"
    assert client_package_name("Global") == "global_client"
    assert client_package_name("Match") == "match"  # a soft keyword is a fine package


def test_a_keyword_named_client_is_a_package_python_imports(tmp_path: Path) -> None:
    resolved = product()
    nodes = (n for c in resolved.system.containers for n in c.nodes)
    reader = next(n for n in nodes if n.eClass.name == "Reader")
    reader.name = "Import"
    root = write_files(clients.generate(resolved), tmp_path) / "clients" / "ros2" / "import_client"
    setup = (root / "setup.py").read_text()
    assert "import_client.reader_node:main" in setup
    ast.parse("from import_client.reader_node import main")
    for module in (root / "import_client").glob("*.py"):
        py_compile.compile(str(module), doraise=True)


def test_a_message_named_like_a_name_of_the_node_module_does_not_replace_it(
    tmp_path: Path,
) -> None:
    # was `from rover_msgs.msg import Node` after `from rclpy.node import Node`: the node
    # class inherited from the message (found by fuzzing)
    resolved = product()
    for node in (n for c in resolved.system.containers for n in c.nodes):
        for interface in node.interfaces:
            if interface.name == "records":
                if getattr(interface, "topic", None) is not None:
                    interface.topic.type = "rover_msgs/Node"
                interface.type = "rover_msgs/Node"
    root = write_files(clients.generate(resolved), tmp_path) / "clients" / "ros2"
    for module in root.glob("*/*/*_node.py"):
        tree = ast.parse(module.read_text())
        bound = {
            alias.asname or alias.name: (statement.module, alias.name)
            for statement in tree.body
            if isinstance(statement, ast.ImportFrom)
            for alias in statement.names
        }
        assert bound["Node"] == ("rclpy.node", "Node"), module
        assert bound["MessageType"] == ("rover_msgs.msg", "Node"), module


def test_one_ament_python_package_per_writer_and_reader(files, tmp_path: Path) -> None:
    root = write_files(files, tmp_path)
    assert sorted(p.name for p in (root / "clients" / "ros2").iterdir()) == sorted(EXPECTED)
    for package, (module, msg_package, msg_name) in EXPECTED.items():
        base = root / "clients" / "ros2" / package
        manifest = etree.parse(str(base / "package.xml")).getroot()
        assert manifest.get("format") == "3"
        assert manifest.findtext("name") == package
        assert manifest.findtext("export/build_type") == "ament_python"
        assert {e.text for e in manifest.findall("exec_depend")} == {"rclpy", msg_package}
        assert (base / "resource" / package).exists()
        setup = ast.parse((base / "setup.py").read_text())
        strings = {n.value for n in ast.walk(setup) if isinstance(n, ast.Constant)}
        assert f"{package} = {package}.{module}:main" in strings
        assert f"$base/lib/{package}" in (base / "setup.cfg").read_text()
        for source in (base / package).glob("*.py"):
            py_compile.compile(str(source), doraise=True)
        node = ast.parse((base / package / f"{module}.py").read_text())
        imports = {
            (n.module, a.name)
            for n in ast.walk(node)
            if isinstance(n, ast.ImportFrom)
            for a in n.names
        }
        assert (f"{msg_package}.msg", msg_name) in imports
        assert ("rclpy.node", "Node") in imports
        calls = {ast.unparse(n.func) for n in ast.walk(node) if isinstance(n, ast.Call)}
        kind = "create_subscription" if module == "writer_node" else "create_publisher"
        assert f"self.{kind}" in calls


def test_clients_carry_no_secret(files) -> None:
    text = b"".join(files.values()).decode()
    assert "POSITION_STORE_TOKEN" in text and "FOLLOW_STORE_TOKEN" in text
    assert "Bearer {self.token}" in text and "test-token" not in text


def test_the_writer_robot_id_defaults_to_the_container_endpoint(files) -> None:
    node = files["clients/ros2/velocity_writer/velocity_writer/writer_node.py"].decode()
    assert "declare_parameter(\"robot_id\", 'ev3_a')" in node


def test_invalid_message_types_and_mismatched_stores_are_refused() -> None:
    resolved = product()
    writer = next(
        n for c in resolved.system.containers for n in c.nodes if n.name == "PositionWriter"
    )
    writer.interfaces[0].topic.type = "rover_msgs/Position; import os"
    with pytest.raises(ModelError, match="invalid message type"):
        clients.generate(resolved)
    resolved = product()
    reader = next(
        n for c in resolved.system.containers for n in c.nodes if n.name == "CommandReader"
    )
    reader.dataType = reader.store.raw
    with pytest.raises(ModelError, match="CommandReader reads Velocity, which store FollowStore"):
        clients.generate(resolved)


def test_generation_is_deterministic(files) -> None:
    assert clients.generate(product()) == files
