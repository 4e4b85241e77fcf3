"""The imported line as the text of its files: ``.tsm``, ``.fm``, ``.rm``, products, report.

The text is written for a reader who will edit it next (docs/import.md): one node per
block, the group of each argument's values in the feature tree, one ``when`` block per
feature with its requirements, implementations and parameters. Everything is in a fixed
order (nodes as roslaunch loaded them, features as the ``--arg`` options gave them), so
the same launch files give the same bytes. Nodes are always named with their container
in the ``.rm`` (``Robot.rviz``): a node may be declared in two containers.
"""

from __future__ import annotations

from spl.core.diagnostics import counted
from spl.importers.graph.master import Graph
from spl.importers.graph.statements import interface_statements, topic_statements
from spl.importers.launch.reading import Omission
from spl.importers.launch.variability import Condition, ImportedLine, ImportedNode
from spl.importers.naming import string_literal

INDENT = "    "


def tsm_text(line: ImportedLine, sources: list[str], graph: Graph | None = None) -> str:
    """The ``.tsm``; with a live ``graph`` of the same system, the nodes it runs get their
    topics, services and actions (``spl import launch --graph``)."""
    out = [f"// Imported by spl import launch from {', '.join(sources)} (docs/import.md).", ""]
    out.append(f"system {line.name}")
    containers: dict[str, list] = {}
    for node in line.nodes:
        containers.setdefault(node.container, []).append(node)
    order = sorted(containers, key=lambda c: (not containers[c][0].robot, c))
    places = {ros_name(n): (n.container, n.name) for n in line.nodes}
    bridges: list[str] = []
    for container in order:
        nodes = containers[container]
        side = "robot" if nodes[0].robot else "cloud"
        out += ["", f"{side} container {container} {{"]
        if nodes[0].robot:
            # launch files do not say how the robot reaches the cloud (docs/import.md)
            out.append(f'{INDENT}endpoint user "{line.name}" password env "RCE_PASSWORD"')
        if nodes[0].namespace:
            out.append(f"{INDENT}namespace {string_literal('/' + nodes[0].namespace)}")
        topics: dict[str, str] = {}
        if graph is not None:
            running = [graph.nodes[r] for n in nodes if (r := ros_name(n)) in graph.nodes]
            topic_lines, topics = topic_statements(graph, running, [])  # noted before
            out += [f"{INDENT}{text}" for text in topic_lines]
        for number, node in enumerate(nodes):
            if number or nodes[0].namespace:
                out.append("")
            out.append(f"{INDENT}// {node.source}")
            optional = "optional " if node.optional else ""
            out.append(f"{INDENT}{optional}node {node.name} {{")
            package, executable = node.implementation
            implementation = f"{INDENT * 2}implementation {package}/{executable}"
            if node.args:
                implementation += f" args {string_literal(node.args)}"
            out.append(implementation)
            for parameter in node.parameters:
                value = f" = {parameter.default}" if parameter.default is not None else ""
                out.append(f"{INDENT * 2}param {parameter.name} : {parameter.type}{value}")
            if graph is not None and ros_name(node) in graph.nodes:
                live = graph.nodes[ros_name(node)]
                statements = interface_statements(graph, live, topics, places, bridges)
                out += [f"{INDENT * 2}{text}" for text in statements]
            out.append(f"{INDENT}}}")
        out.append("}")
    if bridges:
        out += ["", *bridges]
    return "\n".join(out) + "\n"


def ros_name(node: ImportedNode) -> str:
    return f"/{node.namespace}/{node.name}" if node.namespace else f"/{node.name}"


def graph_omissions(line: ImportedLine, graph: Graph) -> list[Omission]:
    """What of a live graph the line cannot hold: nodes no launch file starts, topics of
    an unknown type."""
    started = {ros_name(n) for n in line.nodes}
    found = [
        Omission("", 0, f"node {name} runs in the graph, but no launch file starts it: left out")
        for name in sorted(graph.nodes.keys() - started)
    ]
    notes: list[str] = list(graph.unreadable)
    topic_statements(graph, (graph.nodes[n] for n in sorted(started & graph.nodes.keys())), notes)
    return found + [Omission("", 0, note.removeprefix("warning: ")) for note in notes]


def fm_text(line: ImportedLine, sources: list[str]) -> str:
    out = [
        f"// Imported by spl import launch from {', '.join(sources)}: one feature per",
        "// launch argument given values (docs/import.md).",
        f"feature model {line.name}",
        "",
    ]
    out.append(f"root {line.name} {{")
    fixed = []
    for index, argument in enumerate(line.arguments):
        if len(argument.values) == 1:
            fixed.append(f"{argument.name}:={argument.values[0]}")
            continue
        if argument.is_switch:
            condition = line.features[(index, argument.values[0])]
            assert condition is not None
            out.append(f"{INDENT}optional {condition.feature}    // {argument.name}:=true")
            continue
        members = [c.feature for v in argument.values if (c := line.features[(index, v)])]
        out.append(f"{INDENT}mandatory {line.groups[index]} xor {{ {' '.join(members)} }}")
    for feature in line.combination_features.values():
        out.append(f"{INDENT}optional {feature}")
    out.append("}")
    if fixed:
        out.insert(2, f"// fixed for every product: {' '.join(fixed)}")
    if line.combination_features:
        out += ["", "constraints {"]
        for values, feature in line.combination_features.items():
            parts = [
                _term(c) for i, v in enumerate(values) if (c := line.features[(i, v)]) is not None
            ]
            out.append(f"{INDENT}{feature} <=> {' and '.join(parts)}")
        out.append("}")
    return "\n".join(out) + "\n"


def _term(condition: Condition) -> str:
    return condition.feature if condition.selected else f"not {condition.feature}"


def rm_text(line: ImportedLine, stem: str, sources: list[str]) -> str:
    out = [f"// Imported by spl import launch from {', '.join(sources)} (docs/import.md).", (
        f"resolution model {line.name}"), f'tsm "{stem}.tsm"', f'fm  "{stem}.fm"']  # fmt: skip
    for condition in sorted(line.blocks, key=lambda c: _condition_order(line, c)):
        statements = line.blocks[condition]
        state = "selected" if condition.selected else "not selected"
        out += ["", f"when {condition.feature} {state} {{"]
        if statements.requires:
            names = ", ".join(f"{n.container}.{n.name}" for n in statements.requires)
            out.append(f"{INDENT}require {names}")
        for node, (package, executable, args) in statements.implementations:
            named = f"{node.container}.{node.name}"
            command = f"{INDENT}implementation {named} = {package}/{executable}"
            if args != node.args:  # the node's own otherwise (docs/rm.md)
                command += f" args {string_literal(args)}"
            out.append(command)
        for node, name, value in statements.parameters:
            out.append(f"{INDENT}parameter {node.container}.{node.name}.{name} = {value}")
        out.append("}")
    return "\n".join(out) + "\n"


def _condition_order(line: ImportedLine, condition: Condition) -> tuple[int, int, bool]:
    for (index, value), known in line.features.items():
        if known == condition:
            return (index, line.arguments[index].values.index(value), not condition.selected)
    combinations = list(line.combination_features.values())
    return (len(line.arguments), combinations.index(condition.feature), False)


def product_files(line: ImportedLine) -> dict[str, str]:
    """``products/<values>.yaml`` for every combination."""
    files = {}
    for name, values, features in line.products:
        given = " ".join(f"{a.name}:={v}" for a, v in zip(line.arguments, values, strict=True))
        text = f"product: {name}\nfeatures: [{', '.join(features)}]\n"
        text = f"# {given}\n{text}" if given else text
        files[f"products/{name}.yaml"] = text
    return files


def report_text(line: ImportedLine) -> str:
    """What could not be carried over, one located line each."""
    head = f"spl import launch: {counted(len(line.warnings), 'thing')} not carried over"
    return "\n".join([head, *(str(w) for w in line.warnings)]) + "\n"
