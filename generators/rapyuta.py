"""Rapyuta (RoboEarth Cloud Engine) configuration: one rce-ros file per robot container.

Sharing placement (SPEC 5.2) is :mod:`spl.resolver.placement`'s rule: a TSM cloud
container ``C`` becomes up to three Rapyuta containers, ``<C>_<robotID>`` for private
nodes (one per robot), ``<C>_<group>`` for protected nodes (one per group; carries
``"group": "<group>"``) and ``<C>_public`` for public nodes.

A robot *uses* ``C`` when endpoint connections link the two, directly or through other
cloud containers (robots never relay for each other). Each robot's file declares its
private containers and every shared container it uses; a shared container is declared
with the same nodes, parameters and interfaces in every file that names it (its
interfaces are the union over all robots), so applying the files of a group creates it
once. A private container serves its own robot alone: data of another robot reaches it,
or leaves it for another robot, only through a shared container's nodes. A connection
is written in the file of the robot it belongs to (its robot or private container is
one side), and a connection between two shared containers in every file declaring both.

Wiring. Instead of copying the TSM's endpoint interfaces, every data flow of the
architecture is followed from the node that produces it to each node that consumes it
(a publisher's topic, across endpoint connections, to the subscribers of every topic
reached; a client, through any chain of endpoint stand-ins, to the real server). A flow
whose two nodes end up in different Rapyuta endpoints (robot, or one partition of a
cloud container) becomes one bridge: a Subscriber where the data is produced and a
Publisher where it is consumed, or a ServiceProvider next to the client and a
ServiceClient next to the server. Bridges are keyed by their two ends, so several
nodes sharing a topic or a server share one bridge; flows inside one endpoint, and
containers that only relay, need nothing. This also bridges the partitions of one TSM
container (a private MapOptimizer calling a protected Database). Interface tags are
the TSM's canonical endpoint-interface names: ``sub_<Topic>``, ``pub_<Topic>``,
``srv_<ServerNode>_<service>``, ``cli_<ServerNode>_<service>``; robots take
``...Converter`` types, containers ``...Interface`` types; connections run from the
side the data or call enters (``tagA``) to the side that delivers it (``tagB``).

Parameters are set as ``/<nTag>/<param>`` (under the container's namespace, if any):
int, double and bool values are typed JSON; a yaml value is parsed and written as JSON
when it is a scalar or a list of scalars (what the engine's format carries), otherwise
as its YAML text. The password is the placeholder ``${VAR}`` naming the endpoint's
environment variable; a deployment substitutes it (``envsubst``), never this file.

The JSON is written with sorted keys, lists in a fixed order, indent 2 and a final
newline, then checked against the shipped schema and the engine's rules before it is
returned: a file the engine would refuse is never emitted.
"""

from __future__ import annotations

import json
import math
import re
from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import yaml

from spl.diagnostics import Diagnostic, ModelError, location_of
from spl.generators.rapyuta_rules import check_all
from spl.generators.ros1 import server_ros_name, topic_ros_name
from spl.resolver.placement import MODES, Place, Placement, container_of, sharing_mode
from spl.resolver.product import NodeInterfaces, ResolvedProduct

ENV_VAR = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


@dataclass(frozen=True, order=True)
class Bridge:
    """One connection: data or calls enter at ``source`` and are delivered at ``target``."""

    source: Place
    source_tag: str
    target: Place
    target_tag: str

    def as_json(self) -> dict[str, str]:
        return {
            "tagA": f"{self.source.tag}/{self.source_tag}",
            "tagB": f"{self.target.tag}/{self.target_tag}",
        }


def _ros_name(name: str, namespace: str | None) -> str:
    """``name`` as seen from the container's namespace (global and private names stay)."""
    if not namespace or name.startswith(("/", "~")):
        return name
    return f"/{namespace.strip('/')}/{name}"


def _topic_name(topic: Any) -> str:
    """The topic's ROS name exactly as the launch files remap to it."""
    return _ros_name(topic_ros_name(topic), topic.eContainer().namespace)


def _service_name(server: Any, container: Any, system: Any) -> str:
    """The ROS name a server (or stand-in) is called by in ``container``, as in launch."""
    return _ros_name(server_ros_name(server, system), container.namespace)


def _end(
    place: Place, tag: str, role: str, cls: str | None, addr: str, element: Any
) -> tuple[Place, str, dict[str, str], Any]:
    """One side of a bridge: the interface ``tag`` on ``place`` and its engine entry."""
    suffix = "Converter" if place.is_robot else "Interface"
    spec = {
        "eTag": place.tag,
        "iTag": tag,
        "iType": f"{role}{suffix}",
        "iCls": cls or "",
        "addr": addr,
    }
    return place, tag, spec, element


class _Wiring:
    """Every bridge of the system, over the views of all robots, and their interfaces."""

    def __init__(self, system: Any, placement: Placement, errors: list[Diagnostic]) -> None:
        self.system = system
        self.placement = placement
        self.errors = errors
        self.interfaces: dict[tuple[str, str], dict[str, str]] = {}
        self.bridges: dict[int, set[Bridge]] = {}
        T = placement.T
        self.topic_edges: dict[int, list[Any]] = defaultdict(list)
        self.callers_of: dict[int, list[Any]] = defaultdict(list)
        for connection in system.connections:
            source, target = connection.source, connection.target
            if isinstance(source, T.Subscriber) and isinstance(target, T.Publisher):
                if source.topic is not None and target.topic is not None:
                    self.topic_edges[id(source.topic)].append(target.topic)
            elif isinstance(source, T.ServiceServer) and isinstance(target, T.ServiceClient):
                self.callers_of[id(source)].append(target)
        for robot in placement.robots:
            self.bridges[id(robot)] = self._view(robot)

    def _register(self, end: tuple[Place, str, dict[str, str], Any]) -> None:
        place, tag, spec, element = end
        known = self.interfaces.setdefault((place.tag, tag), spec)
        if known != spec:
            self.errors.append(
                Diagnostic(
                    location_of(element),
                    f"interface {place.tag}/{tag} is needed both as {known['iType']} "
                    f"{known['iCls']} on {known['addr']} and as {spec['iType']} "
                    f"{spec['iCls']} on {spec['addr']}: rename a topic or node",
                )
            )

    def _view(self, robot: Any) -> set[Bridge]:
        """The bridges of the system instantiated for ``robot`` that its file declares."""
        placement = self.placement
        robot_id = placement.robot_ids[id(robot)]
        clouds = placement.scope(robot)
        allowed = {id(robot)} | {id(c) for c in clouds}
        for container_id in list(allowed):
            allowed |= {
                n
                for n in placement.neighbours[container_id]
                if placement.is_robot(placement.by_id[n])
            }
        members = [c for c in self.system.containers if id(c) in allowed]

        publishers, subscribers, all_clients = NodeInterfaces.of(members)
        clients = [client for client in all_clients if client.server is not None]
        subscribers_of: dict[int, list[Any]] = defaultdict(list)
        for subscriber in subscribers:
            subscribers_of[id(subscriber.topic)].append(subscriber)

        def foreign(place: Place) -> bool:
            return place.is_robot and place.owner != robot_id

        def mine(place: Place) -> bool:
            return place.owner == robot_id and place.kind in ("robot", "private")

        bridges: set[Bridge] = set()

        def keep(
            source: tuple[Place, str, dict[str, str], Any],
            target: tuple[Place, str, dict[str, str], Any],
        ) -> None:
            """Record a bridge if this robot's file declares it (the others' files do)."""
            a, b = source[0], target[0]
            if (foreign(a) and b.kind == "private") or (foreign(b) and a.kind == "private"):
                return  # a private partition serves its own robot alone
            if mine(a) or mine(b) or (a.shared and b.shared):
                self._register(source)
                self._register(target)
                bridges.add(Bridge(a, source[1], b, target[1]))

        for publisher in publishers:
            node = publisher.eContainer()
            producer = placement.node_place(node, robot)
            for topic in self._reached(publisher.topic, node.eContainer(), allowed):
                for subscriber in subscribers_of.get(id(topic), ()):
                    consumer = placement.node_place(subscriber.eContainer(), robot)
                    source_topic, target_topic = publisher.topic, subscriber.topic
                    if producer == consumer and (
                        _topic_name(source_topic) == _topic_name(target_topic)
                    ):
                        continue
                    if source_topic.type != target_topic.type:
                        self.errors.append(
                            Diagnostic(
                                location_of(subscriber),
                                f"{node.name}.{publisher.name} feeds "
                                f"{subscriber.eContainer().name}.{subscriber.name} with "
                                f"{source_topic.type} but it expects {target_topic.type}",
                            )
                        )
                        continue
                    keep(
                        _end(
                            producer,
                            f"sub_{source_topic.name}",
                            "Subscriber",
                            source_topic.type,
                            _topic_name(source_topic),
                            source_topic,
                        ),
                        _end(
                            consumer,
                            f"pub_{target_topic.name}",
                            "Publisher",
                            target_topic.type,
                            _topic_name(target_topic),
                            target_topic,
                        ),
                    )

        for client in clients:
            node = client.eContainer()
            server = self._real_server(client.server, allowed)
            if server is None:
                continue
            caller_place = placement.node_place(node, robot)
            server_node = server.eContainer()
            server_place = placement.node_place(server_node, robot)
            if caller_place == server_place:
                continue
            tag = f"{server_node.name}_{server.name}"
            keep(
                _end(
                    caller_place,
                    f"srv_{tag}",
                    "ServiceProvider",
                    server.type,
                    _service_name(client.server, node.eContainer(), self.system),
                    client,
                ),
                _end(
                    server_place,
                    f"cli_{tag}",
                    "ServiceClient",
                    server.type,
                    _service_name(server, server_node.eContainer(), self.system),
                    server,
                ),
            )
        return bridges

    def _reached(self, start: Any, home: Any, allowed: set[int]) -> list[Any]:
        """Topics data published on ``start`` arrives at; only clouds and home relay."""
        placement = self.placement
        seen = {id(start): start}
        frontier = [start]
        while frontier:
            topic = frontier.pop()
            container = topic.eContainer()
            if placement.is_robot(container) and container is not home:
                continue
            for target in self.topic_edges.get(id(topic), ()):
                if id(target.eContainer()) in allowed and id(target) not in seen:
                    seen[id(target)] = target
                    frontier.append(target)
        return list(seen.values())

    def _real_server(self, server: Any, allowed: set[int]) -> Any:
        """The node's ServiceServer behind a chain of endpoint stand-ins, if in view."""
        T = self.placement.T
        seen: set[int] = set()
        while server is not None and not isinstance(server.eContainer(), T.Node):
            if id(server) in seen:
                return None
            seen.add(id(server))
            callers = [
                c for c in self.callers_of.get(id(server), ()) if id(container_of(c)) in allowed
            ]
            server = callers[0].server if callers else None
        if server is None or id(server.eContainer().eContainer()) not in allowed:
            return None
        return server


def parameter_value(parameter: Any) -> Any:
    """The JSON value of a parameter from its canonical text, typed as the engine takes it."""
    kind = parameter.type.name if parameter.type is not None else "string"
    text = parameter.value
    if kind == "int":
        return int(text)
    if kind == "double":
        number = float(text)
        if not math.isfinite(number):
            raise ValueError(f"{text!r} is not a finite number")
        return number
    if kind == "bool":
        if text not in ("true", "false"):
            raise ValueError(f"{text!r} is not true or false")
        return text == "true"
    if kind == "yaml":
        data = yaml.safe_load(text)
        if _json_scalar(data) or (isinstance(data, list) and all(map(_json_scalar, data))):
            return data
        return text
    return text


def _json_scalar(value: Any) -> bool:
    if isinstance(value, float):
        return math.isfinite(value)
    return isinstance(value, (str, int, bool))


def _credentials(robot: Any, errors: list[Diagnostic]) -> dict[str, str]:
    endpoint = robot.endpoint
    if endpoint is None:
        errors.append(
            Diagnostic(
                location_of(robot),
                f"robot container {robot.name} has no endpoint (robot_id, url, user, password env)",
            )
        )
        return {}
    where = location_of(endpoint) or location_of(robot)
    values = {
        "url": endpoint.url,
        "userID": endpoint.user,
        "password": endpoint.passwordEnv,
    }
    for key, value in values.items():
        if not value:
            errors.append(
                Diagnostic(
                    where,
                    f"robot container {robot.name}: the endpoint "
                    f"has no {key} (needed by the rce-ros client)",
                )
            )
    env = endpoint.passwordEnv
    if env and not ENV_VAR.fullmatch(env):
        errors.append(
            Diagnostic(
                where,
                f"robot container {robot.name}: password env {env!r} "
                "is not an environment variable name",
            )
        )
    return {
        "url": endpoint.url or "",
        "userID": endpoint.user or "",
        "password": f"${{{env}}}",
    }


def _partition_entries(
    place: Place, cloud: Any, nodes: Iterable[Any], errors: list[Diagnostic]
) -> tuple[dict[str, Any], list[dict[str, Any]], list[dict[str, Any]]]:
    container: dict[str, Any] = {"cTag": place.tag}
    if place.kind == "protected":
        container["group"] = place.owner
    for resource in ("size", "cpu", "memory", "bandwidth"):
        value = getattr(cloud, resource)
        if value is not None:
            container[resource] = value
    node_entries, parameter_entries = [], []
    namespace = cloud.namespace
    for node in sorted(nodes, key=lambda n: n.name):
        if not node.package or not node.executable:
            errors.append(
                Diagnostic(
                    location_of(node),
                    f"node {node.name} has no implementation (package/executable)",
                )
            )
            continue
        entry = {
            "cTag": place.tag,
            "nTag": node.name,
            "pkg": node.package,
            "exe": node.executable,
            "name": node.name,
        }
        if node.args:
            entry["args"] = node.args
        if namespace:
            entry["namespace"] = namespace
        node_entries.append(entry)
        for parameter in node.parameters:
            if parameter.value is None:
                continue  # left to the node's default: nothing to set
            try:
                value = parameter_value(parameter)
            except (ValueError, yaml.YAMLError) as error:
                errors.append(
                    Diagnostic(
                        location_of(parameter), f"parameter {node.name}.{parameter.name}: {error}"
                    )
                )
                continue
            parameter_entries.append(
                {
                    "cTag": place.tag,
                    "name": _ros_name(f"{node.name}/{parameter.name}", namespace)
                    if namespace
                    else f"/{node.name}/{parameter.name}",
                    "value": value,
                }
            )
    return container, node_entries, parameter_entries


def configurations(system: Any) -> dict[str, dict[str, Any]]:
    """The rce-ros configuration of every robot container, by container name."""
    errors: list[Diagnostic] = []
    placement = Placement(system, errors)
    wiring = _Wiring(system, placement, errors)
    documents: dict[str, dict[str, Any]] = {}
    for robot in placement.robots:
        robot_id = placement.robot_ids[id(robot)]
        document: dict[str, Any] = {**_credentials(robot, errors), "robotID": robot_id}
        declared = {robot_id}
        containers, nodes, parameters = [], [], []
        for cloud in placement.scope(robot):
            by_mode: dict[str, list[Any]] = defaultdict(list)
            for node in cloud.nodes:
                by_mode[sharing_mode(node)].append(node)
            for mode in MODES:
                if not by_mode[mode]:
                    continue
                place = placement.place(cloud, mode, robot)
                container, node_entries, parameter_entries = _partition_entries(
                    place, cloud, by_mode[mode], errors
                )
                declared.add(place.tag)
                containers.append(container)
                nodes.extend(node_entries)
                parameters.extend(parameter_entries)
        interfaces = [spec for key, spec in wiring.interfaces.items() if key[0] in declared]
        connections = [b.as_json() for b in wiring.bridges[id(robot)]]
        lists = {
            "containers": sorted(containers, key=lambda c: c["cTag"]),
            "nodes": sorted(nodes, key=lambda n: (n["cTag"], n["nTag"])),
            "parameters": sorted(parameters, key=lambda p: (p["cTag"], p["name"])),
            "interfaces": sorted(interfaces, key=lambda i: (i["eTag"], i["iTag"])),
            "connections": sorted(connections, key=lambda c: (c["tagA"], c["tagB"])),
        }
        document.update({key: value for key, value in lists.items() if value})
        documents[robot.name] = document
    if errors:
        raise ModelError(_unique(errors))
    return documents


def _unique(errors: list[Diagnostic]) -> list[Diagnostic]:
    return list(dict.fromkeys(errors))


def render(document: dict[str, Any]) -> bytes:
    """Deterministic JSON: sorted keys, indent 2, final newline."""
    return (json.dumps(document, indent=2, sort_keys=True, allow_nan=False) + "\n").encode()


def generate(product: ResolvedProduct) -> dict[str, bytes]:
    """``rapyuta/<robot>.json`` for every robot container of the product."""
    documents = configurations(product.system)
    names = [f"{name}.json" for name in documents]
    problems = check_all(list(documents.values()), names)
    if problems:
        raise ModelError(
            [Diagnostic(None, f"generated Rapyuta configuration refused: {p}") for p in problems]
        )
    return {f"rapyuta/{name}.json": render(doc) for name, doc in sorted(documents.items())}
