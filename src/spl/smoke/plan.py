"""What a smoke rehearsal expects: the live graph the resolved model describes.

The plan is read from the bundle alone: ``resolved.tsm`` (parsed with spl's own .tsm
language) says which nodes, interfaces, types, topics, services, stores and endpoint
connections the product has. Writers and readers are started by the bundle's ROS 1
launch files like every node: the generated nodes themselves when the rehearsal runs the
data path (``generated``), stand-ins otherwise. The topics they write from and read to
carry messages with the fields of their data type (``messages``: one ROS message
definition per type, which the stand-ins and the generated nodes share). From the
model every interface gets the ROS name it must have in its container, and
from its flow table (:mod:`spl.resolver.architecture.flows`, the one Rapyuta, Kubernetes and Zenoh
are generated from):

- a subscriber the ids of the publishers whose data must reach it (the flows into it);
- a service client the id of the node server that must answer it;
- an endpoint subscriber its *relays*: for each endpoint connection it is the source
  of, which messages it passes on (by the publisher that produced them and the
  connections they crossed so far, so the rehearsal carries exactly the table's
  routes: fan-out along every bridge a flow takes, nothing a robot may not relay);
- an endpoint server the peer endpoint client it passes calls (and an action's goals)
  to, and an endpoint action client the endpoint servers it sends the answers back to:
  an action crosses as its five topics, both ways (docs/smoke.md, "Actions").

The stand-ins get a JSON rendering of the plan; the comparison with the live graph
(:mod:`spl.smoke.live`) checks every expectation here.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from spl.metamodels.interface_kinds import InterfaceKind

ENDPOINT = "endpoint"  # how the rehearsal names a container's endpoint node, if free


@dataclass
class Interface:
    container: str
    node: str  # model node name, or the container's endpoint node name
    name: str
    kind: InterfaceKind  # the stand-ins are told its smoke_role
    type: str
    ros_name: str  # the absolute ROS name the model binds it to in its container
    sources: tuple[str, ...] = ()  # subscribers: ids of the publishers that must feed it
    server: str | None = None  # clients: id of the node server that must answer
    forward: tuple[str, str] | None = None  # endpoint server: (peer container, peer client)
    # endpoint action client: the endpoints whose servers' stand-ins it sends answers back to
    peers: tuple[tuple[str, str], ...] = ()
    relays: tuple[Relay, ...] = ()  # endpoint subscriber: where it passes which messages
    # a stand-in publisher on a data-typed topic: the fields it fills and how many
    # messages it sends (after as many subscribers as ``wait_for`` connected)
    values: dict[str, Any] | None = None
    required: bool = True  # must see traffic (endpoint interfaces only when on a path)
    # a node input no flow reaches: the model's word on it, "unfed in the model (SPL045)",
    # "unserved in the model (SPL046)" or "fed from outside the architecture: WHY"
    gap: str = ""
    endpoint: bool = False  # an interface of the container's endpoint, not of a node

    @property
    def id(self) -> str:
        return f"{self.container}.{self.node}.{self.name}"


@dataclass(frozen=True)
class Relay:
    """One endpoint connection from an endpoint subscriber: the peer container and its
    endpoint publisher, the connection's id (messages record the ids they crossed) and
    the messages it passes on, as ``<publisher id>|<ids crossed so far>``."""

    container: str
    interface: str
    connection: str
    passes: tuple[str, ...]

    def as_json(self) -> dict[str, Any]:
        return {
            "container": self.container,
            "interface": self.interface,
            "connection": self.connection,
            "passes": list(self.passes),
        }


@dataclass
class Parameter:
    name: str
    ros_name: str
    value: Any  # the typed value the parameter server must hold


@dataclass
class NodePlan:
    container: str
    name: str  # model name, or the endpoint's (see endpoint_name)
    ros_name: str  # the node's full ROS name
    # launched (a stand-in roslaunch starts) | generated (the bundle's own node) |
    # endpoint | probe (the rehearsal's own subscriber to a generated reader's topic)
    role: str
    interfaces: list[Interface] = field(default_factory=list)
    parameters: list[Parameter] = field(default_factory=list)


@dataclass
class ContainerPlan:
    name: str
    namespace: str  # "" or an absolute namespace without trailing slash
    nodes: list[NodePlan] = field(default_factory=list)

    @property
    def endpoint(self) -> NodePlan | None:
        return next((n for n in self.nodes if n.role == "endpoint"), None)


@dataclass
class SmokePlan:
    product: str
    containers: list[ContainerPlan]
    # ROS type -> message definition, for the types of writers' and readers' topics: the
    # data type's fields, and the stand-ins' tracking fields
    messages: dict[str, str] = field(default_factory=dict)

    @property
    def runs_data(self) -> bool:
        """Whether the bundle's own writers and readers run (the data path)."""
        return any(n.role == "generated" for c in self.containers for n in c.nodes)

    def interfaces(self) -> list[Interface]:
        return [i for c in self.containers for n in c.nodes for i in n.interfaces]

    def stand_in_description(self, status_dir: Path) -> dict[str, Any]:
        """The JSON the stand-ins read: their interfaces by node ROS name."""
        containers = {}
        for container in self.containers:
            nodes = {}
            endpoint = None
            for node in container.nodes:
                entry = {
                    "id": f"{container.name}.{node.name}",
                    "ros_name": node.ros_name,
                    "interfaces": [
                        {
                            "name": i.name,
                            "kind": i.kind.smoke_role,
                            "type": i.type,
                            "ros_name": i.ros_name,
                            "forward": list(i.forward) if i.forward else None,
                            "peers": [list(peer) for peer in i.peers],
                            # the ROS 1 topics the interface is under its name, if several
                            "parts": [
                                {
                                    "suffix": part.suffix,
                                    "from_consumer": part.from_consumer,
                                    "type": part.message_of(i.type),
                                }
                                for part in i.kind.family.ros1_topics
                            ],
                            "relays": [relay.as_json() for relay in i.relays],
                            "values": i.values,
                        }
                        for i in node.interfaces
                    ],
                }
                if node.role == "endpoint":
                    endpoint = entry
                else:
                    nodes[node.ros_name] = entry
            containers[container.name] = {"nodes": nodes, "endpoint": endpoint}
        return {"status_dir": str(status_dir), "containers": containers,
                "messages": self.messages}  # fmt: skip


def join(namespace: str, name: str) -> str:
    """``name`` resolved in ``namespace`` the way roslaunch and rospy resolve it."""
    return name if name.startswith("/") else f"{namespace}/{name}"


def node_ros_name(namespace: str, name: str) -> str:
    """The full ROS name of node ``name`` started in ``namespace`` ("" for the root)."""
    return join(namespace, name) if namespace else f"/{name}"


def namespace_of(container: Any) -> str:
    return "/" + container.namespace.strip("/") if container.namespace else ""


def endpoint_name(taken: set[str], namespace: str, base: str = ENDPOINT) -> str:
    """The node name of a container's endpoint stand-in: ``endpoint``, or ``endpoint_2``,
    ``endpoint_3``... when a node of the container already has that name or ROS name
    (``taken`` holds both). The stand-in is a node of the container's ROS graph: one
    sharing a node's name would make the master shut the other down, and its interfaces'
    ids would meet that node's."""
    candidate, number = base, 1
    while candidate in taken or node_ros_name(namespace, candidate) in taken:
        number += 1
        candidate = f"{base}_{number}"
    return candidate
