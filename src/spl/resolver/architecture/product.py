"""What the Resolution Engine hands to the generators: one resolved product.

Generators read only this: the resolved architecture (a ``tsm.System`` that already
carries the sharing mode of every node, the implementations, parameter values and the
endpoint interfaces and connections created by migrations), plus the facts about the
product that are not part of an architecture (its name, the completed feature
selection, attribute values, which nodes were migrated).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

from spl.core.diagnostics import Diagnostic, Location
from spl.resolver.architecture.flows import FlowTable

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

# a feature attribute's value in a product, typed as the attribute is declared (int,
# double, bool, string; None: declared without a default and given none)
AttributeValue = int | float | bool | str | None


@dataclass(frozen=True)
class NodeMigration:
    """A node moved from one container to another by a ``migrate`` transformation."""

    node: str
    source: str
    target: str
    location: Location | None = None


@dataclass
class ResolvedProduct:
    name: str
    system: tsm_types.System  # the resolved architecture
    features: tuple[str, ...]  # the completed selection, sorted
    attributes: dict[str, AttributeValue] = field(default_factory=dict)  # "Feature.attr" ->
    migrations: tuple[NodeMigration, ...] = ()
    warnings: tuple[Diagnostic, ...] = ()
    # (container, reason) of every container pruning left out: no file of the bundle
    # deploys it (a robot container none of whose nodes the selection uses)
    left_out: tuple[tuple[str, str], ...] = ()

    def migrated(self, node_name: str) -> NodeMigration | None:
        return next((m for m in self.migrations if m.node == node_name), None)

    @cached_property
    def flows(self) -> FlowTable:
        """Who talks to whom in the resolved architecture, computed once: every output
        that moves data reads it (docs/semantics.md, "Flows")."""
        return FlowTable.of(self.system)


def node_keys(
    system: tsm_types.System, left_out: dict[int, list[tsm_types.Node]] | None = None
) -> dict[int, str]:
    """How reports name each node of ``system`` (by ``id``): its name, or
    ``CONTAINER.NODE`` when two containers hold a node of that name (docs/semantics.md
    allows it), so a manifest or summary never folds two nodes into one entry. A
    product's copy of its template names with its own the nodes it left out of each
    container (``left_out``, by the container's id: :mod:`spl.resolver.resolution.pruning`)."""
    left = left_out or {}
    nodes = []  # each name read once: the line checks name every node of dozens of products
    for container in system.containers:
        held = container.name
        nodes += [(held, n.name, id(n)) for n in [*container.nodes, *left.get(id(container), ())]]
    counts = Counter(name for _, name, _ in nodes)
    return {key: name if counts[name] == 1 else f"{where}.{name}" for where, name, key in nodes}


def topic_ros_name(topic: tsm_types.Topic) -> str:
    """The ROS name a topic is published under; ``/Name`` when the model leaves it open."""
    return topic.rosName or f"/{topic.name}"
