"""Reading a running ROS 1 graph through its master's API (docs/import.md, "A live
graph").

The master says which node publishes and subscribes which topic, of which type, and
which node serves which service (``getSystemState``, ``getTopicTypes``,
``lookupService``); a service's type is asked of the service itself with a TCPROS probe
(the header exchange ``rosservice type`` makes). The topics of an action are taken
together as the action (:mod:`.actions`). Nothing here needs rospy: XML-RPC and
one socket per service, each with a timeout, so a hung node cannot hang the import.
"""

from __future__ import annotations

import socket
import struct
import xmlrpc.client
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import urlparse

from spl.dsl import rosnames
from spl.importers.graph.actions import GraphAction, find_actions

CALLER = "/spl_import"
TIMEOUT = 10.0  # seconds for one answer of the master, a node or a service
# what every rospy and roscpp node has, and the master's own logging: not the application
LOGGING_TOPICS = {"/rosout", "/rosout_agg"}
LOGGING_SERVICES = ("/get_loggers", "/set_logger_level")
MAX_HEADER = 1 << 20
MAX_SERVICES = 1000  # each is probed, with its own timeout


class GraphUnreadable(Exception):
    """The master could not be read (exit status 1, nothing written)."""


@dataclass
class GraphNode:
    name: str  # the ROS name, /ns/name
    publishes: set[str] = field(default_factory=set)
    subscribes: set[str] = field(default_factory=set)
    serves: set[str] = field(default_factory=set)
    serves_actions: set[str] = field(default_factory=set)  # by the action's ROS name
    calls_actions: set[str] = field(default_factory=set)
    pid: int | None = None


@dataclass
class Graph:
    nodes: dict[str, GraphNode]
    topic_types: dict[str, str]
    service_types: dict[str, str]
    # what is not carried over as the graph has it, and why: names that are no ROS
    # names, services whose type the probe did not get, topics that look like an action's
    # but are not one whole
    unreadable: list[str]
    actions: dict[str, GraphAction] = field(default_factory=dict)  # by ROS name


class _Transport(xmlrpc.client.Transport):
    def make_connection(self, host):
        connection = super().make_connection(host)
        connection.timeout = TIMEOUT
        return connection


def _call(uri: str, method: str, *args: object) -> Any:
    """The value of a ROS XML-RPC call (``[code, message, value]``)."""
    try:
        proxy = xmlrpc.client.ServerProxy(uri, transport=_Transport(), allow_none=False)
        code, message, value = getattr(proxy, method)(CALLER, *args)
    except (OSError, xmlrpc.client.Error, ValueError, TypeError) as exc:
        raise GraphUnreadable(f"{uri}: {method} failed: {exc}") from None
    if code != 1:
        raise GraphUnreadable(f"{uri}: {method}: {message}")
    return value


def read_graph(master: str) -> Graph:
    """The application's part of the graph the master at ``master`` knows. Its answers
    are input like any other: one of the wrong shape is refused, and a name that is no
    valid ROS name is reported and left out."""
    try:
        return _read_graph(master)
    except (TypeError, ValueError, AttributeError) as exc:
        raise GraphUnreadable(f"{master}: not a ROS master's answer ({exc})") from None


def _valid(name: object, dropped: list[str], what: str) -> bool:
    if isinstance(name, str) and name.startswith("/") and rosnames.is_graph_name(name):
        return True
    dropped.append(f"{what} {str(name)[:80]!r} left out: not a valid global ROS name")
    return False


def _logging_service(name: str) -> bool:
    return name.endswith(LOGGING_SERVICES)


def _entries(
    pairs: list[list[Any]], logging: Callable[[str], bool], dropped: list[str], what: str
) -> Iterator[tuple[str, str]]:
    """``(name, node)`` of a part of the system state, without the logging ones."""
    for name, nodes in pairs:
        if not isinstance(nodes, list):
            raise TypeError(f"the nodes of {what} {str(name)[:80]!r} are not a list")
        if not _valid(name, dropped, what) or logging(name):
            continue
        for node in nodes:
            if _valid(node, dropped, "node"):
                yield name, node


def _read_graph(master: str) -> Graph:
    publishers, subscribers, services = _call(master, "getSystemState")
    if sum(len(names) for _, names in services) > MAX_SERVICES:
        raise GraphUnreadable(f"{master}: more than {MAX_SERVICES} services")
    nodes: dict[str, GraphNode] = {}
    dropped: list[str] = []

    def node(name: str) -> GraphNode:
        return nodes.setdefault(name, GraphNode(name))

    for topic, name in _entries(publishers, LOGGING_TOPICS.__contains__, dropped, "topic"):
        node(name).publishes.add(topic)
    for topic, name in _entries(subscribers, LOGGING_TOPICS.__contains__, dropped, "topic"):
        node(name).subscribes.add(topic)
    for service, name in _entries(services, _logging_service, dropped, "service"):
        node(name).serves.add(service)
    nodes.pop("/rosout", None)
    nodes.pop(CALLER, None)
    topic_types = dict(_call(master, "getTopicTypes"))
    service_types: dict[str, str] = {}
    unreadable: list[str] = sorted(set(dropped))
    actions, notes = find_actions(
        {n.name: n.publishes for n in nodes.values()},
        {n.name: n.subscribes for n in nodes.values()},
        topic_types,
    )
    unreadable += notes
    for action in actions:
        for user in (action.server, *action.clients):
            nodes[user].publishes -= set(action.topics)
            nodes[user].subscribes -= set(action.topics)
        nodes[action.server].serves_actions.add(action.name)
        for client in action.clients:
            nodes[client].calls_actions.add(action.name)
    for graph_node in nodes.values():
        for service in sorted(graph_node.serves):
            try:
                uri = str(_call(master, "lookupService", service))
                service_types[service] = probe_service_type(uri, service)
            except GraphUnreadable as exc:
                unreadable.append(f"service {service}: {exc}")
        graph_node.pid = _pid(master, graph_node.name)
    return Graph(nodes, topic_types, service_types, unreadable, {a.name: a for a in actions})


def _pid(master: str, name: str) -> int | None:
    try:
        pid = _call(str(_call(master, "lookupNode", name)), "getPid")
    except GraphUnreadable:
        return None
    return pid if isinstance(pid, int) else None


def probe_service_type(uri: str, service: str) -> str:
    """The type a service server announces in its TCPROS header, asked with ``probe``."""
    parsed = urlparse(uri)
    if parsed.scheme != "rosrpc" or not parsed.hostname or not parsed.port:
        raise GraphUnreadable(f"not a rosrpc address: {uri!r}")
    fields = {"callerid": CALLER, "service": service, "md5sum": "*", "probe": "1"}
    encoded = [f"{k}={v}".encode() for k, v in fields.items()]
    header = b"".join(struct.pack("<I", len(f)) + f for f in encoded)
    try:
        with socket.create_connection((parsed.hostname, parsed.port), timeout=TIMEOUT) as s:
            s.sendall(struct.pack("<I", len(header)) + header)
            answer = _read_header(s)
    except OSError as exc:
        raise GraphUnreadable(f"{uri}: {exc}") from None
    if "type" not in answer:
        raise GraphUnreadable(f"{uri}: no type in its answer ({answer.get('error', '')})")
    return answer["type"]


def _read_header(connection: socket.socket) -> dict[str, str]:
    (size,) = struct.unpack("<I", _read(connection, 4))
    if size > MAX_HEADER:
        raise OSError(f"a header of {size} bytes")
    data, at = _read(connection, size), 0
    fields: dict[str, str] = {}
    while at + 4 <= len(data):
        (length,) = struct.unpack("<I", data[at : at + 4])
        key, _, value = data[at + 4 : at + 4 + length].decode("utf-8", "replace").partition("=")
        fields[key] = value
        at += 4 + length
    return fields


def _read(connection: socket.socket, size: int) -> bytes:
    chunks: list[bytes] = []
    left = size
    while left:
        chunk = connection.recv(min(left, 65536))
        if not chunk:
            raise OSError("the service closed the connection")
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)
