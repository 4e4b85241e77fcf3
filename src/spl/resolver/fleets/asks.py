"""What one robot of a fleet asks of the shared cloud instances (protected, public) its
product uses: where each shared node runs, its sharing mode and every aspect a product
decides about it (:func:`spl.resolver.resolution.effects.observed`), and the differences between
two robots' asks, which the fleet check reports as conflicts (:mod:`spl.resolver.fleets.fleet`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

from spl.metamodels.interface_kinds import kind_of
from spl.resolver.architecture.placement import SHARED_MODES, Placement, sharing_mode
from spl.resolver.fleets.fleet_file import FleetRobot
from spl.resolver.resolution.effects import PLACEMENT, SHARING, observed, origin_of, real_server

if TYPE_CHECKING:
    from spl.metamodels import tsm_types
    from spl.resolver.architecture.product import ResolvedProduct
    from spl.resolver.resolution.effects import Value

AMBIGUOUS_SERVER = "SPL049"  # a shared node whose client reaches a server per group/robot


@dataclass(frozen=True)
class Ask:
    """What one robot asks of one shared node: the instance and the node's aspects."""

    robot: str
    group: str
    key: tuple[str, str]  # (template container, node)
    mode: str  # protected | public
    placement: str  # the container the node runs in
    on_robot: bool
    tag: str  # the instance (placement rule), e.g. MappingCloud_lab
    values: tuple[tuple[str, Value], ...]  # implementation, parameters, topics, servers

    @property
    def node(self) -> str:
        return self.key[1]

    def value(self, aspect: str) -> Value:
        if aspect == PLACEMENT:
            return self.placement
        if aspect == SHARING:
            return self.mode
        return dict(self.values).get(aspect)

    def where(self) -> str:
        if self.on_robot:
            return f"on robot container {self.placement}"
        scope = f"group {self.group}" if self.mode == "protected" else "every group"
        return f"{self.tag}, {self.mode} for {scope}"


def shared_asks(robot: FleetRobot, product: ResolvedProduct, placement: Placement) -> list[Ask]:
    """What ``robot`` asks of every node it runs as protected or public."""
    asks = []
    for container in product.system.containers:
        for node in container.nodes:
            mode = sharing_mode(node)
            if mode not in SHARED_MODES:
                continue
            place = placement.node_place(node, None)
            values = {
                k: v for k, v in observed(node, product).items() if k not in (PLACEMENT, SHARING)
            }
            values.update(_server_instances(robot, node, product, placement))
            asks.append(
                Ask(
                    robot.name,
                    robot.group,
                    (origin_of(node, product), node.name),
                    mode,
                    container.name,
                    place.is_robot,
                    place.tag,
                    tuple(sorted(values.items())),
                )
            )
    return asks


SERVER_INSTANCE = "server instance of "


def _server_instances(
    robot: FleetRobot, node: tsm_types.Node, product: ResolvedProduct, placement: Placement
) -> dict[str, str]:
    """The instance each cloud server the shared node calls runs in, for this robot: one
    shared instance cannot call two (a public node's protected server is its group's, a
    private one the robot's own)."""
    found = {}
    for interface in node.interfaces:
        kind = kind_of(interface)
        if not kind.calls:
            continue
        server = real_server(kind.bound_to(interface), product.system)
        if server is None or placement.is_robot(server.eContainer().eContainer()):
            continue
        server_node = cast("tsm_types.Node", server.eContainer())  # a node's server
        mode = sharing_mode(server_node)
        if mode == "private":  # robotIDs aside, equal selections share one resolution
            where = f"{server_node.eContainer().name}, private to robot {robot.name}"
        else:
            tag = placement.node_place(server_node, None).tag
            owner = f"group {robot.group}" if mode == "protected" else "every group"
            where = f"{tag}, {mode} for {owner}"
        found[f"{SERVER_INSTANCE}{interface.name}"] = f"{server_node.name} in {where}"
    return found


def scopes(ask: Ask) -> list[tuple[str, str]]:
    """Where an ask is compared: its group, and for a public node all public sharers."""
    return [("group", ask.group)] + ([("public", "")] if ask.mode == "public" else [])


def differences(first: Ask, second: Ask) -> list[str]:
    """The aspects in which two asks of one node in one scope disagree (none when both
    robots run the node on board: then nobody shares it)."""
    if first.on_robot and second.on_robot:
        return []
    if first.placement != second.placement:
        return [PLACEMENT]
    if first.mode != second.mode:
        return [SHARING]
    aspects = sorted({k for k, _ in first.values} | {k for k, _ in second.values})
    differing = [a for a in aspects if first.value(a) != second.value(a)]
    return [  # another server: its instance is not a difference of its own
        a
        for a in differing
        if not a.startswith(SERVER_INSTANCE)
        or f"server of {a.removeprefix(SERVER_INSTANCE)}" not in differing
    ]


def shown(ask: Ask, aspect: str) -> str:
    if aspect in (PLACEMENT, SHARING):
        return ask.where()
    value = ask.value(aspect)
    if value is None:
        return "none"
    if isinstance(value, tuple):
        server, container = value
        return f"{server.split('.', 1)[1]} running in {container}"
    return str(value)
