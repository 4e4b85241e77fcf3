"""Pruning (docs/resolution.md, step 5): what a product does not use leaves its architecture.

Elements go in two passes around the endpoint rewiring: optional nodes and stores
nobody kept go first (so their interfaces stop feeding or calling anything), then,
once cross-container wiring has been rebuilt, topics nothing uses any more and
containers left empty.

A container left with no node and no store is not deployed, robot or cloud alike: a
product without the scout drone has no scout launch file, Rapyuta configuration, Zenoh
bridge or Kubernetes reference, rather than empty ones a robotics engineer would have
to recognise as dead. Every generator reads the resolved model, so leaving the
container out of it leaves it out of every target; the product records which
containers were left out and why (manifest ``left_out``, the resolve summary, ``spl
explain``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, TypeVar

from spl.diagnostics import location_of
from spl.emf import remove_all
from spl.resolver.context import qualified
from spl.resolver.trace import Trace

if TYPE_CHECKING:
    from spl.metamodels import tsm_types
    from spl.metamodels.model_types import Many

Optional = TypeVar("Optional", "tsm_types.Node", "tsm_types.Store")  # what a product may drop


def prune_unkept(system: tsm_types.System, kept: set[int], trace: Trace) -> None:
    """Optional elements nobody kept leave; the kept ones are no longer optional, since a
    product has no variability left (its resolved.tsm, resolved again, is itself)."""
    for container in system.containers:
        _prune(container.nodes, "node", kept, trace)
        _prune(container.stores, "store", kept, trace)


def _prune(collection: Many[Optional], what: str, kept: set[int], trace: Trace) -> None:
    removed = []
    for element in collection:
        if element.optional and id(element) in kept:
            element.optional = False
        elif element.optional:
            removed.append(element)
            trace.record(
                qualified(element) if what == "store" else element.name,
                "removed",
                f"optional {what} that no active resolution element requires or transforms",
                location_of(element),
            )
    remove_all(collection, removed)  # named first: qualified needs their container


LEFT_OUT = {
    "RobotContainer": "robot container left with no node in this product: not deployed",
    "CloudContainer": "cloud container left with no node and no store in this product",
}


def prune_unused(system: tsm_types.System, trace: Trace) -> tuple[tuple[str, str], ...]:
    """Remove unused topics and empty containers; returns ``(container, reason)`` for
    every container left out, in model order."""
    used: set[int] = set()
    for container in system.containers:
        interfaces = [i for node in container.nodes for i in node.interfaces]
        interfaces += list(container.endpoint.interfaces)
        used.update(
            id(topic) for i in interfaces if (topic := getattr(i, "topic", None)) is not None
        )
    for container in system.containers:
        for topic in list(container.topics):
            if id(topic) not in used:
                subject = qualified(topic)
                container.topics.remove(topic)  # named first: qualified needs its container
                trace.record(
                    subject,
                    "removed",
                    "no node or endpoint of the product uses this topic",
                    location_of(topic),
                )
    left_out = []
    for container in list(system.containers):
        if not container.nodes and not container.stores:
            reason = LEFT_OUT[container.eClass.name]
            system.containers.remove(container)
            trace.record(container.name, "removed", reason, location_of(container))
            left_out.append((container.name, reason))
    return tuple(left_out)
