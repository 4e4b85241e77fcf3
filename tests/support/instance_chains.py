"""Which private instances a robot's deployment may hold, computed here from the flow
table's rows and the placement rule of docs/deployment.md (not with the resolver's own
decision), and which private instances each output target deploys, read from its files.

A *vertex* is a node as deployed: ``(place tag, node name)``. Each robot's view places
every row between two containers it sees (itself, the clouds it uses, the robots linked
to those) as docs/deployment.md does: a private node in the robot's own instance
``<Container>_<robotID>``, a row between another robot and a private node left out. An
*edge* is a row as placed: a publisher to a subscriber, a client to its server (a
*call*) and the server's answers back.
"""

from __future__ import annotations

import json
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any

import networkx as nx
import yaml
from lxml import etree

Vertex = tuple[str, str]  # (place tag, node name)


def _container(element: Any) -> Any:
    while element.eClass.name not in ("RobotContainer", "CloudContainer"):
        element = element.eContainer()
    return element


def _is_robot(container: Any) -> bool:
    return container.eClass.name == "RobotContainer"


@dataclass
class RobotView:
    """One robot's deployment as the rule places it: its own nodes, the private
    instances it could get (every private node of every cloud it uses), and the edges."""

    robot_id: str
    own: set[Vertex] = field(default_factory=set)
    candidates: set[Vertex] = field(default_factory=set)
    others: set[str] = field(default_factory=set)  # the other robots' tags
    inputs: set[Vertex] = field(default_factory=set)  # cloud nodes some row of the table feeds
    edges: list[tuple[Vertex, Vertex, bool]] = field(default_factory=list)  # giver, taker, call

    def graph(self, calls_only: bool = False) -> nx.DiGraph:
        """The edges between the robot's own nodes, shared instances and its private
        instances (another robot's nodes take no part: a private instance never takes
        another robot's data)."""
        graph = nx.DiGraph()
        graph.add_nodes_from(self.own | self.candidates)
        for giver, taker, trigger in self.edges:
            if giver[0] in self.others or taker[0] in self.others:
                continue
            if trigger or not calls_only:
                graph.add_edge(giver, taker)
        return graph


def robot_views(product: Any) -> dict[str, RobotView]:
    """Every robot's view of ``product``, by robotID."""
    system = product.system
    robots = [c for c in system.containers if _is_robot(c)]
    rid = {id(r): r.endpoint.robotId for r in robots}
    linked: dict[int, set[int]] = defaultdict(set)
    for connection in system.connections:
        a, b = _container(connection.source), _container(connection.target)
        linked[id(a)].add(id(b))
        linked[id(b)].add(id(a))
    by_id = {id(c): c for c in system.containers}
    fed = {id(flow.target.eContainer()) for flow in product.flows}
    views = {}
    for robot in robots:
        clouds, todo = set(), [id(robot)]
        while todo:
            for other in linked[todo.pop()]:
                if other not in clouds and not _is_robot(by_id[other]):
                    clouds.add(other)
                    todo.append(other)
        seen = {id(robot)} | clouds
        seen |= {o for c in list(seen) for o in linked[c] if _is_robot(by_id[o])}
        me = rid[id(robot)]

        def place(node: Any, me: str = me) -> tuple[str, str]:
            """(tag, kind) of the instance ``node`` runs in, seen from this robot."""
            container = node.eContainer()
            if _is_robot(container):
                return rid[id(container)], "robot"
            mode = node.sharing.name if node.sharing is not None else "private"
            owner = {"private": me, "protected": container.group or container.name}
            return f"{container.name}_{owner.get(mode, 'public')}", mode

        view = RobotView(me, others=set(rid.values()) - {me})
        view.own = {(me, n.name) for n in robot.nodes}
        view.candidates = {
            (place(n)[0], n.name)
            for c in clouds
            for n in by_id[c].nodes
            if place(n)[1] == "private"
        }
        view.inputs = {
            (place(n)[0], n.name) for c in clouds for n in by_id[c].nodes if id(n) in fed
        }
        for flow in product.flows:
            source_container, target_container = flow.source_container, flow.target_container
            if id(source_container) not in seen or id(target_container) not in seen:
                continue
            source_node, target_node = flow.source.eContainer(), flow.target.eContainer()
            (source, source_kind), (target, target_kind) = place(source_node), place(target_node)
            foreign = {
                tag for tag, kind in ((source, source_kind), (target, target_kind))
                if kind == "robot" and tag != me
            }  # fmt: skip
            if foreign and "private" in (source_kind, target_kind):
                continue  # a private instance serves its own robot alone
            giver, taker = (source, source_node.name), (target, target_node.name)
            view.edges.append((giver, taker, True))
            if str(flow.kind) == "service":
                view.edges.append((taker, giver, False))  # the answers
        views[me] = view
    return views


def fleet_views(deployment: Any) -> tuple[dict[str, RobotView], set[str]]:
    """Every robot's view of a deployed fleet (each robot's own product), and the tags
    of every private instance any of them may hold."""
    views: dict[str, RobotView] = {}
    for entry in deployment.robots:
        views |= robot_views(entry.product)
    private = {tag for view in views.values() for tag, _ in view.candidates}
    return views, private


def chained(view: RobotView, deployed: set[Vertex]) -> set[Vertex]:
    """The instances of ``deployed`` joined with the robot's own nodes by a chain of
    edges, either way, directly or through an instance joined so (docs/deployment.md:
    an instance chained only to another of the robot's kept instances is kept)."""
    graph = view.graph()
    joined = set(view.own)
    while True:
        reach = set()
        for vertex in joined:
            reach |= nx.descendants(graph, vertex) | nx.ancestors(graph, vertex)
        new = (reach & deployed) - joined
        if not new:
            return joined & deployed
        joined |= new


def fed_by_robot(view: RobotView) -> set[Vertex]:
    """The private instances the robot's own data reaches through publications and
    calls (through shared instances and its other private instances): each must be
    deployed."""
    graph = view.graph(calls_only=True)
    reached = set()
    for vertex in view.own:
        reached |= nx.descendants(graph, vertex)
    return reached & view.candidates


def idle(view: RobotView, deployed: set[Vertex]) -> set[Vertex]:
    """The deployed private instances nothing can feed: a node some row of the table
    feeds, with no row of the robot's view bringing it anything from the robot's own
    nodes, a shared instance or another deployed instance of the robot."""
    feeding = {
        taker
        for giver, taker, trigger in view.edges
        if trigger
        and giver[0] not in view.others
        and (giver not in view.candidates or giver in deployed)
    }
    return {v for v in deployed if v in view.inputs and v not in feeding}


# -- what each target deploys -------------------------------------------------------------
def _launch_nodes(text: str | bytes) -> set[str]:
    data = text.encode() if isinstance(text, str) else text
    return {node.get("name") for node in etree.fromstring(data).iter("node")}


def kubernetes_instances(files: dict[str, bytes]) -> dict[str, set[str]]:
    """Private instance tag -> the nodes its ConfigMap's launch file starts."""
    found: dict[str, set[str]] = {}
    for path, data in files.items():
        if not path.startswith("kubernetes/") or not path.endswith(".yaml"):
            continue
        for document in yaml.load_all(data, Loader=yaml.CSafeLoader):  # libyaml's safe loader
            labels = (document or {}).get("metadata", {}).get("labels", {})
            if document["kind"] == "ConfigMap" and labels.get("spl.robotics/sharing") == "private":
                found[labels["spl.robotics/placement"]] = _launch_nodes(
                    document["data"]["launch.xml"]
                )
    return found


def rapyuta_instances(files: dict[str, bytes], private: set[str]) -> dict[str, set[str]]:
    """Instance tag (of ``private``) -> the nodes the Rapyuta files put there."""
    found: dict[str, set[str]] = defaultdict(set)
    for path, data in files.items():
        if "rapyuta/" not in path or not path.endswith(".json"):
            continue
        document = json.loads(data)  # spl writes Rapyuta files as plain JSON
        for container in document.get("containers", ()):
            if container["cTag"] in private:
                found.setdefault(container["cTag"], set())
        for node in document.get("nodes", ()):
            if node["cTag"] in private:
                found[node["cTag"]].add(node["nTag"])
    return dict(found)


def zenoh_places(files: dict[str, bytes]) -> set[str]:
    """The places with a Zenoh bridge (``zenoh/<tag>.json5``, ``<tag>.2.json5``...)."""
    return {
        path.removeprefix("zenoh/").split(".")[0]
        for path in files
        if path.startswith("zenoh/") and path.endswith(".json5")
    }


def launch_instances(
    files: dict[str, bytes], prefix: str, private: set[str]
) -> dict[str, set[str]]:
    """Instance tag (of ``private``) -> the nodes of ``<prefix>ros1/<tag>.launch``."""
    found = {}
    for path, data in files.items():
        if path.startswith(f"{prefix}ros1/") and path.endswith(".launch"):
            tag = path.removeprefix(f"{prefix}ros1/").removesuffix(".launch")
            if tag in private:
                found[tag] = _launch_nodes(data)
    return found


def as_vertices(instances: dict[str, set[str]]) -> set[Vertex]:
    return {(tag, node) for tag, nodes in instances.items() for node in nodes}


def check_instances(views: dict[str, RobotView], deployed: set[Vertex]) -> None:
    """Every robot's deployed private instances are chained to it and fed, and every
    instance its own data reaches is deployed."""
    for view in views.values():
        tags = {tag for tag, _ in view.candidates}
        mine = {v for v in deployed if v[0] in tags}
        assert chained(view, mine) == mine, view.robot_id
        assert not idle(view, mine), (view.robot_id, sorted(idle(view, mine)))
        assert fed_by_robot(view) <= mine, view.robot_id


def check_product_instances(product: Any, files: dict[str, bytes]) -> None:
    """What :func:`check_instances` asks, of a product's bundle (its Kubernetes and
    Rapyuta files, which must deploy the same private instances)."""
    views = robot_views(product)
    private = {tag for view in views.values() for tag, _ in view.candidates}
    kubernetes = as_vertices(kubernetes_instances(files))
    assert kubernetes == as_vertices(rapyuta_instances(files, private))
    check_instances(views, kubernetes)
