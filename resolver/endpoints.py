"""Endpoint interfaces and endpoint connections: how a bridge exists in the model.

Exactly as in the Rapyuta metamodel, data crossing containers goes through each
container's endpoint: an endpoint Subscriber takes a topic of its own container and
sends it over an EndpointConnection to an endpoint Publisher, which publishes it in
the other container; an endpoint ServiceServer stands in for a remote server and an
endpoint ServiceClient calls the real one. Interfaces have canonical names so one
topic or server is never bridged twice and the .tsm printer can write them back as
``bridge`` statements.
"""

from __future__ import annotations

from typing import Any

from spl.metamodels import tsm


def subscriber_name(topic: Any) -> str:
    return f"sub_{topic.name}"


def publisher_name(topic: Any) -> str:
    return f"pub_{topic.name}"


def stand_in_name(server: Any) -> str:
    return f"srv_{server.eContainer().name}_{server.name}"


def caller_name(server: Any) -> str:
    return f"cli_{server.eContainer().name}_{server.name}"


def _find_or_add(container: Any, kind: str, name: str, **features: Any) -> Any:
    endpoint = container.endpoint
    for interface in endpoint.interfaces:
        if interface.name == name and interface.eClass.name == kind:
            return interface
    interface = getattr(tsm(), kind)(name=name, **features)
    endpoint.interfaces.append(interface)
    return interface


def endpoint_subscriber(container: Any, topic: Any) -> Any:
    return _find_or_add(
        container, "Subscriber", subscriber_name(topic), topic=topic, type=topic.type
    )


def endpoint_publisher(container: Any, topic: Any) -> Any:
    return _find_or_add(container, "Publisher", publisher_name(topic), topic=topic, type=topic.type)


def endpoint_stand_in(container: Any, server: Any) -> Any:
    """An endpoint ServiceServer in ``container`` offering ``server``'s service there."""
    return _find_or_add(
        container, "ServiceServer", stand_in_name(server), type=server.type, rosName=server.rosName
    )


def endpoint_caller(container: Any, server: Any) -> Any:
    """An endpoint ServiceClient in ``container`` calling the real ``server``."""
    return _find_or_add(
        container, "ServiceClient", caller_name(server), server=server, type=server.type
    )


def connect(system: Any, source: Any, target: Any) -> Any:
    """The EndpointConnection source -> target, created once."""
    for connection in system.connections:
        if connection.source is source and connection.target is target:
            return connection
    connection = tsm().EndpointConnection(source=source, target=target)
    system.connections.append(connection)
    return connection


def topic_bridge(system: Any, source_topic: Any, target_topic: Any) -> Any:
    source_container, target_container = source_topic.eContainer(), target_topic.eContainer()
    return connect(
        system,
        endpoint_subscriber(source_container, source_topic),
        endpoint_publisher(target_container, target_topic),
    )


def service_bridge(system: Any, client: Any, server: Any) -> Any:
    """Serve ``server`` to ``client`` (a node interface in another container)."""
    client_container = client.eContainer().eContainer()
    stand_in = endpoint_stand_in(client_container, server)
    client.server = stand_in
    return connect(system, stand_in, endpoint_caller(server.eContainer().eContainer(), server))


def is_endpoint_interface(interface: Any) -> bool:
    return isinstance(interface.eContainer(), tsm().Endpoint)
