"""Random small product lines for the migration property tests.

A :class:`LineSpec` is drawn by hypothesis (2-4 robot and cloud containers, topics,
nodes with publishers, subscribers, service servers and clients, topic and service
bridges, and resolution elements migrating nodes or requiring optional ones, each
under its own optional feature) and written as .tsm/.fm/.rm text. The spec is the
test's own record of the template: the expected data flows are computed from it, not
from anything the engine builds.

Templates are well formed by construction: bridged topics have one type, a ROS name
always has the same type, and no chain of bridges brings data back into a container
it left (a hairpin in the template itself, which docs/resolution.md forbids in results).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import networkx as nx
from hypothesis import strategies as st

# ROS name -> message type: one ROS name never carries two types.
ROS_TOPICS = {
    "/scan": "sensor_msgs/LaserScan",
    "/scan_filtered": "sensor_msgs/LaserScan",
    "/pose": "geometry_msgs/PoseStamped",
    "/goal": "geometry_msgs/PoseStamped",
}
TOPIC_NAMES = ("Scan", "Pose", "Data", "Goal")
SERVICE_TYPES = ("nav_msgs/GetPlan", "std_srvs/Trigger")
ACTION_TYPE = "move_base_msgs/MoveBase"


@dataclass
class Topic:
    container: str
    name: str
    ros: str

    @property
    def type(self) -> str:
        return ROS_TOPICS[self.ros]


@dataclass
class Interface:
    kind: str  # publishes | subscribes | provides | calls | provides action | calls action
    name: str
    type: str
    topic: str | None = None  # publishes/subscribes: a topic of the node's container
    server: tuple[str, str] | None = None  # calls: (node, server) in the same container


@dataclass
class Node:
    name: str
    container: str
    optional: bool
    interfaces: list[Interface] = field(default_factory=list)
    sharing: str | None = None  # a cloud node's sharing mode, when the spec gives one


@dataclass
class Element:
    feature: str
    negated: bool
    requires: list[str] = field(default_factory=list)
    migrations: list[tuple[str, str]] = field(default_factory=list)  # (node, target)


@dataclass
class LineSpec:
    containers: dict[str, str]  # name -> robot | cloud, in file order
    topics: list[Topic]
    nodes: list[Node]
    topic_bridges: list[tuple[tuple[str, str], tuple[str, str]]]  # (container, topic) pairs
    service_bridges: list[tuple[tuple[str, str, str], tuple[str, str, str]]]
    elements: list[Element]

    def node(self, name: str) -> Node:
        return next(n for n in self.nodes if n.name == name)

    def features(self) -> list[str]:
        return [e.feature for e in self.elements]


def _bridge_graph(bridges) -> nx.DiGraph:
    graph = nx.DiGraph()
    graph.add_edges_from(bridges)
    return graph


def _returns_to_a_container(graph: nx.DiGraph) -> bool:
    """Some chain of bridges leads from a topic of a container to another one of it."""
    return any(other[0] == topic[0] for topic in graph for other in nx.descendants(graph, topic))


@st.composite
def line_specs(draw) -> LineSpec:
    count = draw(st.integers(2, 4))
    kinds = ["robot", "cloud"] + [
        draw(st.sampled_from(["robot", "cloud"])) for _ in range(2, count)
    ]
    containers = {f"{kind.capitalize()}{i}": kind for i, kind in enumerate(kinds)}
    topics: list[Topic] = []
    for container in containers:
        names = draw(st.lists(st.sampled_from(TOPIC_NAMES), min_size=1, max_size=3, unique=True))
        ros_names = draw(
            st.lists(
                st.sampled_from(sorted(ROS_TOPICS)),
                min_size=len(names),
                max_size=len(names),
                unique=True,
            )
        )
        topics += [Topic(container, n, r) for n, r in zip(names, ros_names, strict=True)]

    nodes: list[Node] = []
    for container in containers:
        local = [t for t in topics if t.container == container]
        for _ in range(draw(st.integers(1, 3))):
            node = Node(f"N{len(nodes)}", container, draw(st.booleans()))
            for k in range(draw(st.integers(1, 3))):
                kind = draw(st.sampled_from(["publishes", "subscribes", "provides", "calls"]))
                name = f"{kind[0]}{k}"
                if kind in ("publishes", "subscribes"):
                    topic = draw(st.sampled_from(local))
                    node.interfaces.append(Interface(kind, name, topic.type, topic=topic.name))
                else:
                    kind_type = draw(st.sampled_from(SERVICE_TYPES))
                    node.interfaces.append(Interface(kind, name, kind_type))
            nodes.append(node)

    # local service bindings: a client may call a server of its own container
    for node in nodes:
        for client in (i for i in node.interfaces if i.kind == "calls"):
            servers = [
                (other.name, i.name)
                for other in nodes
                if other.container == node.container
                for i in other.interfaces
                if i.kind == "provides" and i.type == client.type
            ]
            if servers and draw(st.booleans()):
                client.server = draw(st.sampled_from(servers))

    service_bridges = []
    for node in nodes:
        for client in (i for i in node.interfaces if i.kind == "calls" and i.server is None):
            remote = [
                (other.container, other.name, i.name)
                for other in nodes
                if other.container != node.container
                for i in other.interfaces
                if i.kind == "provides" and i.type == client.type
            ]
            if remote and draw(st.booleans()):
                server = draw(st.sampled_from(remote))
                service_bridges.append(((node.container, node.name, client.name), server))

    candidates = [
        ((a.container, a.name), (b.container, b.name))
        for a in topics
        for b in topics
        if a.container != b.container and a.type == b.type
    ]
    topic_bridges: list = []
    drawn = (
        draw(st.lists(st.sampled_from(candidates), max_size=5, unique=True)) if candidates else []
    )
    for bridge in drawn:
        if not _returns_to_a_container(_bridge_graph([*topic_bridges, bridge])):
            topic_bridges.append(bridge)

    elements: list[Element] = []
    movable = draw(st.lists(st.sampled_from([n.name for n in nodes]), max_size=4, unique=True))
    for node_name in movable:
        targets = [
            c for c in containers if c != next(n for n in nodes if n.name == node_name).container
        ]
        migration = (node_name, draw(st.sampled_from(targets)))
        if elements and draw(st.booleans()) and not elements[-1].requires:
            elements[-1].migrations.append(migration)  # two migrations in one element
        else:
            elements.append(Element(f"M{len(elements)}", draw(st.booleans()), [], [migration]))
    optional = [n.name for n in nodes if n.optional]
    for node_name in (
        draw(st.lists(st.sampled_from(optional), max_size=3, unique=True)) if optional else []
    ):
        elements.append(Element(f"K{len(elements)}", draw(st.booleans()), [node_name]))
    return LineSpec(containers, topics, nodes, topic_bridges, service_bridges, elements)


@st.composite
def fleet_specs(draw, actions: bool = False) -> LineSpec:
    """A line of 2-3 robots and 1-3 clouds that exchange data: every container has topics
    of some shared ROS names, robot and cloud topics of one ROS name are bridged up, down
    or not at all (and clouds among themselves now and then), cloud nodes get a sharing
    mode, robot clients call cloud servers through service bridges, and a few elements
    migrate nodes or require optional ones. Fan-out, fan-in, private partitions used by
    several robots and flows between robots through the cloud are common. With
    ``actions``, cloud nodes may serve an action and robot nodes call one, through action
    bridges as services do (without, the draws are those of a line with none)."""
    robots = draw(st.integers(2, 3))
    clouds = draw(st.integers(1, 3))
    containers = {f"Robot{i}": "robot" for i in range(robots)}
    containers |= {f"Cloud{i}": "cloud" for i in range(robots, robots + clouds)}
    ros_names = sorted(ROS_TOPICS)[:3]
    topics = []
    for container in containers:
        chosen = draw(st.lists(st.sampled_from(ros_names), min_size=1, max_size=3, unique=True))
        topics += [Topic(container, TOPIC_NAMES[ros_names.index(r)], r) for r in sorted(chosen)]
    nodes: list[Node] = []
    for container, kind in containers.items():
        local = [t for t in topics if t.container == container]
        for _ in range(draw(st.integers(1, 2))):
            node = Node(f"N{len(nodes)}", container, draw(st.booleans()) and bool(nodes))
            if kind == "cloud":
                node.sharing = draw(st.sampled_from(["private", "protected", "public"]))
            kinds = ["publishes", "subscribes"] + (["provides"] if kind == "cloud" else ["calls"])
            if actions:
                kinds.append(f"{kinds[-1]} action")
            for k in range(draw(st.integers(1, 3))):
                what = draw(st.sampled_from(kinds))
                name = f"{what[0]}{'a' if what.endswith('action') else ''}{k}"
                if what in ("publishes", "subscribes"):
                    topic = draw(st.sampled_from(local))
                    node.interfaces.append(Interface(what, name, topic.type, topic=topic.name))
                elif what.endswith("action"):
                    node.interfaces.append(Interface(what, name, ACTION_TYPE))
                else:
                    node.interfaces.append(Interface(what, name, SERVICE_TYPES[0]))
            nodes.append(node)
    bridges: list = []
    for a in topics:
        for b in topics:
            if a.ros != b.ros or containers[a.container] == containers[b.container] == "robot":
                continue
            if a.container == b.container:
                continue
            if (
                draw(
                    st.integers(
                        0,
                        3
                        if "cloud" in (containers[a.container], containers[b.container])
                        and containers[a.container] != containers[b.container]
                        else 9,
                    )
                )
                == 0
            ):
                bridge = ((a.container, a.name), (b.container, b.name))
                if not _returns_to_a_container(_bridge_graph([*bridges, bridge])):
                    bridges.append(bridge)
    service_bridges = []
    for provides in ("provides", "provides action"):  # an action is bridged as a service
        servers = [
            (n.container, n.name, i.name) for n in nodes for i in n.interfaces if i.kind == provides
        ]
        calls = provides.replace("provides", "calls")
        for node in nodes:
            for client in (i for i in node.interfaces if i.kind == calls):
                if servers and draw(st.booleans()):
                    server = draw(st.sampled_from(servers))
                    service_bridges.append(((node.container, node.name, client.name), server))
    elements: list[Element] = []
    for node in draw(st.lists(st.sampled_from(nodes), max_size=2, unique_by=lambda n: n.name)):
        targets = [c for c in containers if c != node.container]
        migration = (node.name, draw(st.sampled_from(targets)))
        elements.append(Element(f"M{len(elements)}", draw(st.booleans()), [], [migration]))
    optional = [n.name for n in nodes if n.optional]
    if optional:
        required = draw(st.lists(st.sampled_from(optional), max_size=len(optional), unique=True))
        if required:
            elements.append(Element(f"K{len(elements)}", False, required))
    return LineSpec(containers, topics, nodes, bridges, service_bridges, elements)


# -- writing the line ------------------------------------------------------------------
def tsm_text(spec: LineSpec) -> str:
    lines = ["system Random", ""]
    for container, kind in spec.containers.items():
        if kind == "robot":
            lines.append(f"robot container {container} {{")
            lines.append(
                f'    endpoint robot_id "{container.lower()}" url "wss://cloud.example.org:9000/"'
                ' user "tester" password env "RCE_PASSWORD"'
            )
        else:
            lines.append(f"cloud container {container} {{")
        for topic in (t for t in spec.topics if t.container == container):
            lines.append(f'    topic {topic.name} : {topic.type} name "{topic.ros}"')
        for node in (n for n in spec.nodes if n.container == container):
            sharing = f" sharing {node.sharing}" if node.sharing else ""
            lines.append(f"    {'optional ' if node.optional else ''}node {node.name}{sharing} {{")
            lines.append(f"        implementation pkg/{node.name.lower()}")
            for i in node.interfaces:
                if i.kind == "publishes":
                    lines.append(f"        publishes {i.name} -> {i.topic}")
                elif i.kind == "subscribes":
                    lines.append(f"        subscribes {i.name} <- {i.topic}")
                elif i.kind.startswith("provides"):
                    ros = f"/{node.name.lower()}/{i.name}"
                    lines.append(f'        {i.kind} {i.name} : {i.type} name "{ros}"')
                elif i.kind == "calls action":
                    lines.append(f"        calls action {i.name} : {i.type}")
                elif i.server is not None:
                    lines.append(f"        calls {i.name} -> {i.server[0]}.{i.server[1]}")
                else:
                    lines.append(f"        calls {i.name} : {i.type}")
            lines.append("    }")
        lines += ["}", ""]
    for (a, t1), (b, t2) in spec.topic_bridges:
        lines.append(f"bridge {a}.{t1} -> {b}.{t2}")
    for client, server in spec.service_bridges:
        lines.append(f"bridge {'.'.join(client)} -> {'.'.join(server)}")
    return "\n".join(lines) + "\n"


def fm_text(spec: LineSpec) -> str:
    children = "".join(f"    optional {f}\n" for f in spec.features())
    return f"feature model Random\n\nroot Root {{\n{children}}}\n"


def rm_text(spec: LineSpec) -> str:
    lines = ["resolution model Random", 'tsm "random.tsm"', 'fm "random.fm"', ""]
    for element in spec.elements:
        state = "not selected" if element.negated else "selected"
        lines.append(f"when {element.feature} {state} {{")
        if element.requires:
            lines.append(f"    require {', '.join(element.requires)}")
        lines += [f"    migrate {node} to {target}" for node, target in element.migrations]
        lines.append("}")
    return "\n".join(lines) + "\n"


def write_line(spec: LineSpec, directory: Path) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    (directory / "random.tsm").write_text(tsm_text(spec), encoding="utf-8")
    (directory / "random.fm").write_text(fm_text(spec), encoding="utf-8")
    (directory / "random.rm").write_text(rm_text(spec), encoding="utf-8")
    return directory
