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

An optional node or store that no other declaration of the template refers into (no
topic, server or store of it is used from outside it) and no active resolution element
names is dropped before anything reads it: nothing can keep it, so the first pass
removes it whatever happens before. The engine does not copy it at all
(:func:`left_out`): a product costs what it keeps, and such a node or store is only
recorded as removed, where the first pass would have removed its copy
(``tests/resolver/test_dropped_containers.py``, ``tests/resolver/test_left_out_copies.py``).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, TypeVar

from spl.core.diagnostics import location_of
from spl.core.emf import references, remove_all
from spl.resolver.architecture.flows import bound_topic
from spl.resolver.resolution.context import qualified
from spl.resolver.resolution.trace import Trace

if TYPE_CHECKING:
    from spl.metamodels import rm_types, tsm_types
    from spl.metamodels.model_types import Many

Optional = TypeVar("Optional", "tsm_types.Node", "tsm_types.Store")  # what a product may drop


Unreferred = dict[int, int]  # id of each element in such a node or store -> the node's id


def unreferred_optionals(template: tsm_types.System) -> Unreferred:
    """The optional nodes and stores of ``template`` that no element outside them refers
    into, each with the elements it holds (built once per line: a scan of the template)."""
    unit: dict[int, int] = {}  # every element of an optional node or store -> its id
    for container in template.containers:
        for element in [*container.nodes, *container.stores]:
            if element.optional:
                unit[id(element)] = id(element)
                unit.update((id(inner), id(element)) for inner in element.eAllContents())
    referred = {
        into
        for source, _, target in references(template)
        if (into := unit.get(id(target))) is not None and unit.get(id(source)) != into
    }
    return {e: u for e, u in unit.items() if u not in referred}


def left_out(unreferred: Unreferred, active: Iterable[rm_types.ResolutionElement]) -> set[int]:
    """The ids of the optional nodes and stores a product with the ``active`` elements
    drops before anything reads them: those of ``unreferred`` no active element names
    (nor anything in them)."""
    named = {
        unit
        for element in active
        for _, _, target in references(element)
        if (unit := unreferred.get(id(target))) is not None
    }
    return {u for u in unreferred.values() if u not in named}


def prune_unkept(
    system: tsm_types.System,
    kept: set[int],
    trace: Trace,
    template: tsm_types.System | None = None,
    left: set[int] | None = None,
) -> None:
    """Optional elements nobody kept leave; the kept ones are no longer optional, since a
    product has no variability left (its resolved.tsm, resolved again, is itself).
    ``system`` copies ``template`` but the nodes and stores ``left`` (:func:`left_out`):
    they are recorded as removed where the copy would have held them."""
    for at, container in enumerate(system.containers):
        original = template.containers[at] if template is not None and left else None
        for what in ("node", "store"):
            collection = getattr(container, f"{what}s")
            members = list(collection)
            if original is not None:
                members = _with_left_out(getattr(original, f"{what}s"), members, left or set())
            _prune(container, what, members, kept, trace)


def _with_left_out(template: Many[Optional], copied: list[Optional], left: set[int]) -> list:
    """The members of a collection of a copy (``copied``) with those of the template's
    it left out (``left``) put back where the template has them. The copied members
    follow the template's order, then come those moved in (a migration appends); a
    migrated node is kept, so where it goes changes no record."""
    members: list[Optional] = []
    at = 0
    for original in template:
        if id(original) in left:
            members.append(original)
        elif at < len(copied) and copied[at].name == original.name:
            members.append(copied[at])
            at += 1
    return members + copied[at:]


def _prune(
    container: tsm_types.Container,
    what: str,
    members: list[Optional],
    kept: set[int],
    trace: Trace,
) -> None:
    removed = []
    for element in members:
        if not element.optional:  # read once: each read is a call of pyecore's descriptor
            continue
        if id(element) in kept:
            element.optional = False
        else:
            if element.eContainer() is container:  # not the template's, left out
                removed.append(element)
            trace.record(
                qualified(element) if what == "store" else element.name,
                "removed",
                f"optional {what} that no active resolution element requires or transforms",
                location_of(element),
            )
    remove_all(getattr(container, f"{what}s"), removed)  # named first: qualified needs it


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
        used.update(id(topic) for i in interfaces if (topic := bound_topic(i)) is not None)
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
