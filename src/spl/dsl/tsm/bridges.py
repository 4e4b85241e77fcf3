"""Bridges of the .tsm language: data and service calls crossing containers.

A bridge is not an element of its own: exactly as in the Rapyuta metamodel it becomes
one endpoint interface in each container plus an ``EndpointConnection``. The endpoint
interfaces get canonical names (the ``endpoint_*_name`` functions) which the resolver's
node migration uses too, so the printer can write every connection back as a bridge.
"""

from __future__ import annotations

from collections.abc import Iterator
from itertools import count
from typing import TYPE_CHECKING, Any

from spl.dsl.tsm.calling import call_problem
from spl.dsl.tsm.names import Names, find_interface
from spl.metamodels.interface_kinds import TOPIC, InterfaceKind, kind_of, side

if TYPE_CHECKING:
    from spl.metamodels import tsm_types


# -- canonical endpoint interface names (shared with the resolver) ---------------------
# Each begins with the endpoint prefix of its interface's kind (``InterfaceKind``), so
# that endpoint interfaces of different kinds never share a name.
def endpoint_subscriber_name(topic: Any) -> str:
    """The endpoint Subscriber sending ``topic`` out of its container."""
    return f"{side(TOPIC, False).endpoint_prefix}_{topic.name}"


def endpoint_publisher_name(topic: Any) -> str:
    """The endpoint Publisher publishing bridged data on ``topic``."""
    return f"{side(TOPIC, True).endpoint_prefix}_{topic.name}"


def endpoint_server_name(server: Any) -> str:
    """The endpoint server (of the kind of node server ``server``: ``srv_`` for a
    service's, ``asrv_`` for an action's) standing in for ``server`` elsewhere."""
    return f"{kind_of(server).endpoint_prefix}_{server.eContainer().name}_{server.name}"


def endpoint_client_name(server: Any) -> str:
    """The endpoint client (``cli_``, ``acli_``) calling node server ``server`` in its
    container."""
    prefix = side(kind_of(server).family, False).endpoint_prefix
    return f"{prefix}_{server.eContainer().name}_{server.name}"


def endpoint_name_choices(name: str, target: Any) -> Iterator[str]:
    """The names an endpoint interface for ``target`` (a topic or a node server) may
    take, in order: its canonical ``name``; qualified with the container of ``target``
    (``srv_C2_Db_get``); then numbered. Canonical names can coincide: ``srv_Db_get``
    stands for server ``Db.get`` of any cloud container, ``srv_a_b_c`` for ``a_b.c`` and
    ``a.b_c``. The first bridge takes the first name free and a later one for another
    target the next, in the order bridges are made, which the printer keeps; so every
    interface of an endpoint has a name of its own and a resolved model parses back to
    the same names."""
    yield name
    owner = target.eContainer()
    if owner.eClass.name == "Node":
        owner = owner.eContainer()
    prefix, _, rest = name.partition("_")
    qualified = f"{prefix}_{owner.name}_{rest}"
    yield qualified
    for number in count(2):
        yield f"{qualified}_{number}"


def bridged_clients(stand_in: Any) -> Iterator[tuple[Any, Any]]:
    """Node clients bound to the endpoint server ``stand_in``, in model order."""
    container = stand_in.eContainer().eContainer()
    for node in container.nodes:
        for interface in node.interfaces:
            kind = kind_of(interface)
            if kind.calls and kind.bound_to(interface) is stand_in:
                yield node, interface


# -- building -----------------------------------------------------------------------------
class Bridges:
    """Turns the ``bridge`` statements of one file into endpoint interfaces and connections.

    Indexes what it has created, so each bridge costs a few dictionary look-ups, not a
    scan of every connection and endpoint interface made before it.
    """

    def __init__(self, names: Names) -> None:
        self.names = names
        self.connections = names.system.connections
        self._pairs: set[tuple[int, int]] = set()  # (source id, target id) connected
        self._from: dict[int, list[Any]] = {}  # source id -> its connections, in order
        self._topic_pairs: dict[tuple[int, int], Any] = {}  # topic ids -> first connection
        self._interfaces: dict[tuple[int, str], Any] = {}  # (endpoint id, name) -> interface

    def add(self, tree: Any) -> None:
        """The endpoint interfaces and connection of one ``bridge`` statement."""
        names = self.names
        source, target = tree.source.parts, tree.target.parts
        if len(source) != len(target) or len(source) not in (2, 3):
            names.error(
                tree.source,
                "a bridge is CONTAINER.TOPIC -> CONTAINER.TOPIC or "
                "CONTAINER.NODE.CLIENT -> CONTAINER.NODE.SERVER",
            )
            return
        containers = [names.container(ref) for ref in (source[0], target[0])]
        if None in containers:
            return
        if containers[0] is containers[1]:
            names.error(target[0], "a bridge connects two different containers")
            return
        if len(source) == 2:
            self._topic_bridge(tree, containers, source[1], target[1])
        else:
            self._service_bridge(tree, containers, source[1:], target[1:])

    def _topic_bridge(self, tree: Any, containers: list, source_ref: Any, target_ref: Any) -> None:
        names = self.names
        source = names.topic(containers[0], source_ref)
        target = names.topic(containers[1], target_ref)
        if source is None or target is None:
            return
        if source.type != target.type:
            names.error(
                target_ref,
                f"type mismatch: {containers[0].name}.{source.name} is {source.type}, "
                f"{containers[1].name}.{target.name} is {target.type}",
            )
            return
        first = self._topic_pairs.get((id(source), id(target)))
        if first is not None:
            names.error(
                tree.source,
                f"duplicate bridge {containers[0].name}.{source.name} -> "
                f"{containers[1].name}.{target.name} (first at line {first.srcLine})",
            )
            return
        subscriber = self._endpoint_interface(
            tree, containers[0], side(TOPIC, False), endpoint_subscriber_name(source), source
        )
        publisher = self._endpoint_interface(
            tree, containers[1], side(TOPIC, True), endpoint_publisher_name(target), target
        )
        if subscriber is not None and publisher is not None:
            self._connect(tree, subscriber, publisher)

    def _member(self, container: Any, node_ref: Any, member_ref: Any) -> Any:
        node = self.names.node(container, node_ref)
        if node is None:
            return None
        member = find_interface(node, member_ref.name)
        if member is None:
            self.names.error(member_ref, f"node {node.name} has no interface {member_ref.name}")
        return member

    def _service_bridge(self, tree: Any, containers: list, source: list, target: list) -> None:
        names = self.names
        client = self._member(containers[0], *source)
        server = self._member(containers[1], *target)
        if client is None or server is None:
            return
        problem = call_problem(client, server, "bridge {client} -> {server}")
        if problem is not None:
            names.error(target[1] if problem.at_server else source[1], problem.message)
            return
        client_kind = kind_of(client)
        provider = side(client_kind.family, True)
        if client.server is not None:
            if client.server.eContainer() is containers[0].endpoint:
                first = self._from[id(client.server)][0]
                names.error(
                    tree.source,
                    f"duplicate bridge for client {source[0].name}.{client.name} "
                    f"(first at line {first.srcLine})",
                )
            else:
                names.error(
                    source[1],
                    f"client {source[0].name}.{client.name} is already bound to "
                    f"{client.server.eContainer().name}.{client.server.name}; declare it "
                    f"unbound ('{client_kind.keyword} {client.name} : TYPE') to bridge it",
                )
            return
        stand_in = self._endpoint_interface(
            tree, containers[0], provider, endpoint_server_name(server), server
        )
        if stand_in is None:
            return
        caller = self._endpoint_interface(
            tree, containers[1], client_kind, endpoint_client_name(server), server
        )
        if caller is None:
            return
        client.server, client.type = stand_in, server.type
        self._connect(tree, stand_in, caller)

    def _endpoint_interface(
        self, tree: Any, container: Any, kind: InterfaceKind, name: str, target: Any
    ) -> Any:
        """The endpoint interface of ``kind`` for ``target`` (the topic it is bound to, or
        the node server it stands in for or calls): reused when it exists, else made under
        the first of its names (:func:`endpoint_name_choices`) no other one has."""
        names = self.names
        endpoint = container.endpoint
        for choice in endpoint_name_choices(name, target):
            existing = self._interfaces.get((id(endpoint), choice))
            if existing is None:
                name = choice
                break
            # An endpoint server is linked to the server it stands in for by its connection.
            if kind_of(existing) is kind and self._serves(existing, kind, target):
                return existing
        # a stand-in server is bound to nothing and answers under the ROS name of the
        # server it stands in for; every other kind is bound to its target
        bound = {kind.binds: target} if kind.binds else {"rosName": target.rosName}
        interface: tsm_types.Interface = getattr(names.T, kind.eclass)(
            name=name, type=target.type, **bound
        )
        endpoint.interfaces.append(names.locate(interface, tree))
        self._interfaces[id(endpoint), name] = interface
        return interface

    def _serves(self, interface: Any, kind: InterfaceKind, target: Any) -> bool:
        """Whether endpoint ``interface`` (of ``kind``) is the one for ``target``: bound
        to it, or (a stand-in server) connected to a caller of it."""
        if kind.binds is not None:
            return kind.bound_to(interface) is target
        return any(c.target.server is target for c in self._from.get(id(interface), ()))

    def _connect(self, tree: Any, source: Any, target: Any) -> None:
        if (id(source), id(target)) in self._pairs:
            return
        connection = self.names.T.EndpointConnection(source=source, target=target)
        self.connections.append(self.names.locate(connection, tree))
        self._pairs.add((id(source), id(target)))
        self._from.setdefault(id(source), []).append(connection)
        source_topic, target_topic = getattr(source, "topic", None), getattr(target, "topic", None)
        if source_topic is not None and target_topic is not None:
            self._topic_pairs.setdefault((id(source_topic), id(target_topic)), connection)
