"""Pruning (SPEC 5.1 step 7): what a product does not use leaves its architecture.

Elements go in two passes around the endpoint rewiring: optional nodes and stores
nobody kept go first (so their interfaces stop feeding or calling anything), then,
once cross-container wiring has been rebuilt, topics nothing uses any more and cloud
containers left empty.
"""

from __future__ import annotations

from typing import Any

from spl.diagnostics import location_of
from spl.resolver.context import qualified
from spl.resolver.trace import Trace


def prune_unkept(system: Any, kept: set[int], trace: Trace) -> None:
    """Optional elements nobody kept leave; the kept ones are no longer optional, since a
    product has no variability left (its resolved.tsm, resolved again, is itself)."""
    for container in system.containers:
        for collection, what in ((container.nodes, "node"), (container.stores, "store")):
            for element in list(collection):
                if element.optional and id(element) in kept:
                    element.optional = False
                elif element.optional:
                    collection.remove(element)
                    trace.record(
                        qualified(element) if what == "store" else element.name,
                        "removed",
                        f"optional {what} that no active resolution element requires or transforms",
                        location_of(element),
                    )


def prune_unused(system: Any, trace: Trace) -> None:
    used: set[int] = set()
    for container in system.containers:
        interfaces = [i for node in container.nodes for i in node.interfaces]
        interfaces += list(container.endpoint.interfaces)
        used.update(id(i.topic) for i in interfaces if getattr(i, "topic", None) is not None)
    for container in system.containers:
        for topic in list(container.topics):
            if id(topic) not in used:
                container.topics.remove(topic)
                trace.record(
                    qualified(topic),
                    "removed",
                    "no node or endpoint of the product uses this topic",
                    location_of(topic),
                )
    for container in list(system.containers):
        if (
            container.eClass.name == "CloudContainer"
            and not container.nodes
            and not container.stores
        ):
            system.containers.remove(container)
            trace.record(
                container.name,
                "removed",
                "cloud container left with no node and no store in this product",
                location_of(container),
            )
