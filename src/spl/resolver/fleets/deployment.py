"""A checked fleet as the generators deploy it: every robot's own product, and every
shared cloud instance once.

Each robot is resolved on its own, so its architecture carries its robotIDs and, on
every cloud container, its group (which names the protected instances it shares, as
the placement rule says). The shared instances are those the fleet check found: one per
tag, with the nodes any robot runs there and the robots using it. The first robot using
an instance is its *reference*: the check made sure every robot asks the same of the
nodes they share, so the instance is generated from the reference's nodes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import ModelError
from spl.resolver.architecture.placement import sharing_mode
from spl.resolver.fleets.fleet import FleetCheck, RobotProduct, robot_selection
from spl.resolver.resolution.engine import resolve

if TYPE_CHECKING:
    from spl.metamodels import tsm_types


@dataclass(frozen=True)
class SharedInstance:
    """One protected or public cloud instance of a TSM container's shared nodes."""

    tag: str  # e.g. MappingCloud_lab
    container: str  # the TSM container it is a partition of
    mode: str  # protected | public
    group: str | None  # protected: the group owning it
    nodes: tuple[str, ...]
    robots: tuple[str, ...]  # in fleet order; the first is the reference


@dataclass
class FleetDeployment:
    check: FleetCheck
    robots: list[RobotProduct]
    shared: list[SharedInstance]

    def reference(self, instance: SharedInstance) -> list[tuple[RobotProduct, tsm_types.Node]]:
        """(robot, node) for every node of the instance, each from the first robot that
        runs it there."""
        chosen: dict[str, tuple[RobotProduct, tsm_types.Node]] = {}
        for entry in self.robots:
            if entry.robot.name not in instance.robots:
                continue
            for container in entry.product.system.containers:
                if container.name != instance.container:
                    continue
                for node in container.nodes:
                    if sharing_mode(node) == instance.mode and node.name in instance.nodes:
                        chosen.setdefault(node.name, (entry, node))
        return [chosen[name] for name in instance.nodes if name in chosen]


def deploy(check: FleetCheck) -> FleetDeployment:
    """The deployment of a fleet that passed its check (refused otherwise)."""
    if not check.ok:
        raise ModelError([d for d in check.diagnostics if d.severity == "error"])
    robots = []
    for robot in check.fleet.robots:
        resolution = resolve(check.line, robot_selection(robot, check.line))
        for container in resolution.product.system.containers:
            if container.eClass.name == "CloudContainer":
                cast("tsm_types.CloudContainer", container).group = robot.group
        robots.append(RobotProduct(robot, resolution))
    shared = []
    for tag, asks in check.instances().items():
        first = asks[0]
        shared.append(
            SharedInstance(
                tag,
                first.placement,
                first.mode,
                first.group if first.mode == "protected" else None,
                tuple(sorted({a.node for a in asks})),
                tuple(dict.fromkeys(a.robot for a in asks)),
            )
        )
    return FleetDeployment(check, robots, shared)
