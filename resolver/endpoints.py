"""Endpoint interfaces and endpoint connections: how a bridge exists in the model.

Exactly as in the Rapyuta metamodel, data crossing containers goes through each
container's endpoint: an endpoint Subscriber takes a topic of its own container and
sends it over an EndpointConnection to an endpoint Publisher, which publishes it in
the other container; an endpoint ServiceServer stands in for a remote server and an
endpoint ServiceClient calls the real one. Interfaces carry the canonical names of the
.tsm language (:mod:`spl.dsl.tsm`), so a topic or server is never bridged twice and the
printer writes them back as ``bridge`` statements. Where two canonical names coincide
(stand-ins for servers ``Db.get`` of two cloud containers), the second interface takes
the next name the language gives it (:func:`spl.dsl.tsm.endpoint_name_choices`), so a
client is never bound to another container's server.
"""

from __future__ import annotations

from typing import Any

from spl.dsl.tsm import (
    endpoint_client_name,
    endpoint_name_choices,
    endpoint_publisher_name,
    endpoint_server_name,
    endpoint_subscriber_name,
)
from spl.metamodels import tsm


class EndpointWiring:
    """Creates endpoint interfaces and connections of one system, each at most once.

    Indexes what the system already holds, so wiring thousands of bridges costs
    thousands of dictionary look-ups, not a scan of every endpoint per bridge.
    """

    def __init__(self, system: Any) -> None:
        self.system = system
        self.interfaces = {
            (id(c), i.eClass.name, i.name): i
            for c in system.containers
            for i in c.endpoint.interfaces
        }
        self.connections = {(id(c.source), id(c.target)) for c in system.connections}
        # what each endpoint interface is for: its topic, or the node server it calls or
        # stands in for (a stand-in knows it through its connection)
        self.targets = {
            id(c.source): c.target.server
            for c in system.connections
            if c.source.eClass.name == "ServiceServer"
        }

    def _target(self, interface: Any) -> Any:
        if interface.eClass.name in ("Subscriber", "Publisher"):
            return interface.topic
        if interface.eClass.name == "ServiceClient":
            return interface.server
        return self.targets.get(id(interface))

    def _find_or_add(
        self, container: Any, kind: str, name: str, target: Any, **features: Any
    ) -> Any:
        """The endpoint interface of ``container`` for ``target``: the one made before,
        else a new one under the first of its names no other interface has."""
        for choice in endpoint_name_choices(name, target):
            interface = self.interfaces.get((id(container), kind, choice))
            if interface is None:
                interface = getattr(tsm(), kind)(name=choice, **features)
                self.interfaces[id(container), kind, choice] = interface
                self.targets[id(interface)] = target
                container.endpoint.interfaces.append(interface)
                return interface
            if self._target(interface) is target:
                return interface
        raise AssertionError("endpoint_name_choices never ends")

    def connect(self, source: Any, target: Any) -> None:
        """The EndpointConnection source -> target, created once."""
        if (id(source), id(target)) not in self.connections:
            self.connections.add((id(source), id(target)))
            self.system.connections.append(tsm().EndpointConnection(source=source, target=target))

    def topic_bridge(self, source_topic: Any, target_topic: Any) -> None:
        """Data published on ``source_topic`` reaches ``target_topic`` in another container."""
        subscriber = self._find_or_add(
            source_topic.eContainer(),
            "Subscriber",
            endpoint_subscriber_name(source_topic),
            source_topic,
            topic=source_topic,
            type=source_topic.type,
        )
        publisher = self._find_or_add(
            target_topic.eContainer(),
            "Publisher",
            endpoint_publisher_name(target_topic),
            target_topic,
            topic=target_topic,
            type=target_topic.type,
        )
        self.connect(subscriber, publisher)

    def service_bridge(self, client: Any, server: Any) -> None:
        """Serve ``server`` to ``client``, a node interface in another container."""
        stand_in = self._find_or_add(
            client.eContainer().eContainer(),
            "ServiceServer",
            endpoint_server_name(server),
            server,
            type=server.type,
            rosName=server.rosName,
        )
        caller = self._find_or_add(
            server.eContainer().eContainer(),
            "ServiceClient",
            endpoint_client_name(server),
            server,
            server=server,
            type=server.type,
        )
        client.server = stand_in
        self.connect(stand_in, caller)


def topic_bridge(system: Any, source_topic: Any, target_topic: Any) -> None:
    """One bridge on its own (a model built by hand); for many, keep an EndpointWiring."""
    EndpointWiring(system).topic_bridge(source_topic, target_topic)


def service_bridge(system: Any, client: Any, server: Any) -> None:
    EndpointWiring(system).service_bridge(client, server)


def is_endpoint_interface(interface: Any) -> bool:
    return isinstance(interface.eContainer(), tsm().Endpoint)
