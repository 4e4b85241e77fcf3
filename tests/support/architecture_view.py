"""A compact, comparable view of a resolved architecture for engine tests."""

from __future__ import annotations

from typing import Any


def where(element: Any) -> str:
    """``Container.Topic`` for topics, ``Container.endpoint.name`` / ``Node.name`` for servers."""
    owner = element.eContainer()
    if owner.eClass.name == "Endpoint":
        return f"{owner.eContainer().name}.endpoint.{element.name}"
    if owner.eClass.name in ("RobotContainer", "CloudContainer"):
        return f"{owner.name}.{element.name}"
    return f"{owner.name}.{element.name}"


def view(system: Any) -> dict[str, Any]:
    placement, bindings, topics, endpoint_interfaces = {}, {}, {}, {}
    for container in system.containers:
        topics[container.name] = sorted(t.name for t in container.topics)
        endpoint_interfaces[container.name] = sorted(
            f"{i.eClass.name}:{i.name}" for i in container.endpoint.interfaces
        )
        for node in container.nodes:
            placement[node.name] = container.name
            for interface in node.interfaces:
                target = getattr(interface, "topic", None) or getattr(interface, "server", None)
                if target is not None:
                    bindings[f"{node.name}.{interface.name}"] = where(target)
    bridges = sorted(f"{where(c.source)} -> {where(c.target)}" for c in system.connections)
    return {
        "placement": placement,
        "bindings": bindings,
        "topics": topics,
        "endpoints": endpoint_interfaces,
        "bridges": bridges,
    }
