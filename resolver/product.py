"""What the Resolution Engine hands to the generators: one resolved product.

Generators read only this: the resolved architecture (a ``tsm.System`` that already
carries the sharing mode of every node, the implementations, parameter values and the
endpoint interfaces and connections created by migrations), plus the facts about the
product that are not part of an architecture (its name, the completed feature
selection, attribute values, which nodes were migrated).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from spl.diagnostics import Diagnostic, Location


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
    system: Any  # tsm.System, the resolved architecture
    features: tuple[str, ...]  # the completed selection, sorted
    attributes: dict[str, Any] = field(default_factory=dict)  # "Feature.attr" -> value
    migrations: tuple[NodeMigration, ...] = ()
    warnings: tuple[Diagnostic, ...] = ()

    def migrated(self, node_name: str) -> NodeMigration | None:
        return next((m for m in self.migrations if m.node == node_name), None)
