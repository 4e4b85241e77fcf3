"""``spl import graph``: a product line from a running ROS 1 graph (docs/import.md, "A
live graph").

What launch files cannot tell, the master can: the topics with their types, who
publishes and subscribes them, the services with their types, and the actions whose
topics actionlib made (:mod:`.master`, :mod:`.actions`). The
graph is one running system, so the line has one product. A node's package and
executable are found from its process (``getPid``, then its command line) in a package
of the package path; a node whose process or package cannot be found cannot be
launched by a bundle and is left out, reported.
"""

from __future__ import annotations

import fnmatch
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from spl.core.diagnostics import counted
from spl.dsl import rosnames
from spl.importers.graph.master import Graph, GraphNode, GraphUnreadable, read_graph
from spl.importers.graph.statements import interface_statements, topic_statements
from spl.importers.naming import is_name, string_literal

__all__ = ["GraphImport", "GraphUnreadable", "import_graph"]

INDENT = "    "


@dataclass(frozen=True)
class GraphImport:
    name: str
    nodes: int
    files: dict[str, str]  # path in the output folder -> text
    warnings: list[str]


def import_graph(
    master: str, name: str, package_path: list[Path], robot_patterns: Sequence[str] = ()
) -> GraphImport:
    """The files of the one-product line of the graph the master at ``master`` knows."""
    graph = read_graph(master)
    warnings = [f"warning: {problem}" for problem in graph.unreadable]
    containers: dict[str, list[tuple[GraphNode, tuple[str, str]]]] = {}
    for ros_name in sorted(graph.nodes):
        node = graph.nodes[ros_name]
        base = ros_name.rsplit("/", 1)[-1]
        implementation = _implementation(node, package_path)
        problem = None if is_name(base) else "its name is not an identifier"
        if implementation is None:
            problem = problem or (
                "its package is not known (its process is not on this machine, or its "
                "executable is in no package of --package-path)"
            )
        if problem or implementation is None:
            warnings.append(f"warning: node {ros_name} left out: {problem}")
            continue
        namespace = ros_name[: -len(base)].strip("/")
        robot = any(fnmatch.fnmatchcase(n, p) for p in robot_patterns for n in (ros_name, base))
        key = ("Robot" if robot else "Cloud") + (
            "_" + namespace.replace("/", "_") if namespace else ""
        )
        containers.setdefault(key, []).append((node, implementation))
    tsm = _tsm_text(name, master, graph, containers, warnings)
    files = {
        f"{name}.tsm": tsm,
        f"{name}.fm": f"// Imported by spl import graph: one product.\nfeature model {name}\n\n"
        f"root {name}\n",
        f"{name}.rm": f'resolution model {name}\ntsm "{name}.tsm"\nfm  "{name}.fm"\n',
        f"products/{name}.yaml": f"product: {name}\nfeatures: [{name}]\n",
        "import-report.txt": "\n".join(
            [f"spl import graph: {counted(len(warnings), 'thing')} not carried over", *warnings]
        )
        + "\n",
    }
    count = sum(len(nodes) for nodes in containers.values())
    return GraphImport(name, count, files, warnings)


def _implementation(node: GraphNode, package_path: list[Path]) -> tuple[str, str] | None:
    """``(package, executable)`` of the node's process: the first file of its command line
    (after the interpreter) inside a package of the package path."""
    if node.pid is None:
        return None
    try:
        words = Path(f"/proc/{node.pid}/cmdline").read_bytes().split(b"\0")
        cwd = Path(os.readlink(f"/proc/{node.pid}/cwd"))
    except OSError:
        return None
    roots = [p.resolve() for p in package_path]
    for word in words[:3]:
        path = cwd / os.fsdecode(word)  # a relative path is the process's working folder's
        if not path.is_file():
            continue
        path = path.resolve()
        for folder in path.parents:
            if not any(folder == r or r in folder.parents for r in roots):
                break
            manifest = folder / "package.xml"
            if manifest.is_file():
                found = re.search(r"<name>\s*([^<\s]+)\s*</name>", manifest.read_text()[:65536])
                package = found.group(1) if found else ""
                if rosnames.problem_package(package) or rosnames.problem_executable(path.name):
                    return None
                return package, path.name
    return None


def _tsm_text(
    name: str,
    master: str,
    graph: Graph,
    containers: dict[str, list[tuple[GraphNode, tuple[str, str]]]],
    warnings: list[str],
) -> str:
    out = [f"// Imported by spl import graph from the ROS master at {master} (docs/import.md).",
           "", f"system {name}"]  # fmt: skip
    places = {
        node.name: (container, node.name.rsplit("/", 1)[-1])
        for container, nodes in containers.items()
        for node, _ in nodes
    }
    bridges: list[str] = []
    for container in sorted(containers, key=lambda c: (not c.startswith("Robot"), c)):
        nodes = containers[container]
        robot = container.startswith("Robot")
        out += ["", f"{'robot' if robot else 'cloud'} container {container} {{"]
        if robot:
            out.append(f'{INDENT}endpoint user "{name}" password env "RCE_PASSWORD"')
        namespace = container.partition("_")[2]
        if namespace:
            first = nodes[0][0].name
            out.append(f"{INDENT}namespace {string_literal(first[: first.rindex('/')])}")
        topic_lines, topics = topic_statements(graph, (n for n, _ in nodes), warnings)
        out += [f"{INDENT}{line}" for line in topic_lines]
        for node, (package, executable) in nodes:
            out += ["", f"{INDENT}node {node.name.rsplit('/', 1)[-1]} {{"]
            out.append(f"{INDENT * 2}implementation {package}/{executable}")
            statements = interface_statements(graph, node, topics, places, bridges)
            out += [f"{INDENT * 2}{line}" for line in statements]
            out.append(f"{INDENT}}}")
        out.append("}")
    if bridges:
        out += ["", *bridges]
    return "\n".join(out) + "\n"
