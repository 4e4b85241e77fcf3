"""Endpoint interfaces and endpoint connections: how a bridge exists in the model.

Exactly as in the Rapyuta metamodel, data crossing containers goes through each
container's endpoint: an endpoint Subscriber takes a topic of its own container and
sends it over an EndpointConnection to an endpoint Publisher, which publishes it in
the other container; an endpoint ServiceServer stands in for a remote server and an
endpoint ServiceClient calls the real one. Interfaces carry the canonical names of the
.tsm language (:mod:`spl.dsl.tsm.language`), so a topic or server is never bridged twice and the
printer writes them back as ``bridge`` statements. Where two canonical names coincide
(stand-ins for servers ``Db.get`` of two cloud containers), the second interface takes
the next name the language gives it (:func:`spl.dsl.tsm.language.endpoint_name_choices`), so a
client is never bound to another container's server.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

from spl.dsl.tsm.language import (
    endpoint_client_name,
    endpoint_name_choices,
    endpoint_publisher_name,
    endpoint_server_name,
    endpoint_subscriber_name,
)
from spl.metamodels import tsm
from spl.metamodels.interface_kinds import TOPIC, InterfaceKind, kind_of, side

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

    # what an endpoint interface is for: the topic it carries, or the node server it
    # calls or stands in for
    Target = tsm_types.Topic | tsm_types.ServiceServer


class EndpointWiring:
    """Creates endpoint interfaces and connections of one system, each at most once.

    Indexes what the system already holds, so wiring thousands of bridges costs
    thousands of dictionary look-ups, not a scan of every endpoint per bridge.
    """

    def __init__(self, system: tsm_types.System) -> None:
        self.system = system
        self.interfaces = {
            (id(c), kind_of(i), i.name): i for c in system.containers for i in c.endpoint.interfaces
        }
        self.connections = {(id(c.source), id(c.target)) for c in system.connections}
        # what each endpoint interface is for: its topic, or the node server it calls or
        # stands in for (a stand-in knows it through its connection)
        self.targets: dict[int, Target | None] = {
            id(c.source): kind_of(c.target).bound_to(c.target)
            for c in system.connections
            if kind_of(c.source).serves
        }

    def _target(self, interface: tsm_types.Interface) -> Target | None:
        kind = kind_of(interface)
        if kind.binds is not None:  # its topic, or the server it calls
            return cast("Target | None", kind.bound_to(interface))
        return self.targets.get(id(interface))  # a stand-in: through its connection

    def _find_or_add(
        self,
        container: tsm_types.Container,
        kind: InterfaceKind,
        name: str,
        target: Target,
        **features: object,
    ) -> tsm_types.Interface:
        """The endpoint interface of ``container`` for ``target``: the one made before,
        else a new one under the first of its names no other interface has."""
        for choice in endpoint_name_choices(name, target):
            interface = self.interfaces.get((id(container), kind, choice))
            if interface is None:
                made: tsm_types.Interface = getattr(tsm(), kind.eclass)(name=choice, **features)
                interface = made
                self.interfaces[id(container), kind, choice] = interface
                self.targets[id(interface)] = target
                container.endpoint.interfaces.append(interface)
                return interface
            if self._target(interface) is target:
                return interface
        raise AssertionError("endpoint_name_choices never ends")

    def connect(self, source: tsm_types.Interface, target: tsm_types.Interface) -> None:
        """The EndpointConnection source -> target, created once."""
        if (id(source), id(target)) not in self.connections:
            self.connections.add((id(source), id(target)))
            self.system.connections.append(tsm().EndpointConnection(source=source, target=target))

    def topic_bridge(self, source_topic: tsm_types.Topic, target_topic: tsm_types.Topic) -> None:
        """Data published on ``source_topic`` reaches ``target_topic`` in another container."""
        subscriber = self._find_or_add(
            cast("tsm_types.Container", source_topic.eContainer()),  # a topic of the system
            side(TOPIC, False),
            endpoint_subscriber_name(source_topic),
            source_topic,
            topic=source_topic,
            type=source_topic.type,
        )
        publisher = self._find_or_add(
            cast("tsm_types.Container", target_topic.eContainer()),
            side(TOPIC, True),
            endpoint_publisher_name(target_topic),
            target_topic,
            topic=target_topic,
            type=target_topic.type,
        )
        self.connect(subscriber, publisher)

    def service_bridge(
        self, client: tsm_types.ServiceClient, server: tsm_types.ServiceServer
    ) -> None:
        """Serve ``server`` to ``client``, a node interface in another container: a
        stand-in of the server's kind next to the client, calling the server through an
        endpoint interface of the client's kind next to the server."""
        calling = kind_of(client)
        stand_in = self._find_or_add(
            client.eContainer().eContainer(),
            side(calling.family, True),
            endpoint_server_name(server),
            server,
            type=server.type,
            rosName=server.rosName,
        )
        caller = self._find_or_add(
            server.eContainer().eContainer(),
            calling,
            endpoint_client_name(server),
            server,
            server=server,
            type=server.type,
        )
        client.server = cast("tsm_types.ServiceServer", stand_in)
        self.connect(stand_in, caller)


def topic_bridge(
    system: tsm_types.System, source_topic: tsm_types.Topic, target_topic: tsm_types.Topic
) -> None:
    """One bridge on its own (a model built by hand); for many, keep an EndpointWiring."""
    EndpointWiring(system).topic_bridge(source_topic, target_topic)


def service_bridge(
    system: tsm_types.System, client: tsm_types.ServiceClient, server: tsm_types.ServiceServer
) -> None:
    EndpointWiring(system).service_bridge(client, server)


def is_endpoint_interface(interface: tsm_types.Interface) -> bool:
    return isinstance(interface.eContainer(), tsm().Endpoint)
