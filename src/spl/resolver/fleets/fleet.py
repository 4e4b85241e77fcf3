"""Fleets: robots of one product line sharing cloud node instances (docs/fleets.md; the
mapping paper's section VII, docs/index.md).

Each robot's product is resolved as usual. A cloud node whose sharing mode is
``protected`` runs once per group, ``public`` once for everybody
(:mod:`spl.resolver.architecture.placement`): every robot using that instance must *ask the same of
it*, since one process cannot run two implementations. What a robot asks of a shared
node is read from its resolved product: where the node runs, its sharing mode,
implementation, parameter values, the topics its interfaces use and the servers its
clients call (:func:`spl.resolver.resolution.effects.observed`).

Robots are compared in file order with the first robot that fixed the node in their
scope (their group; and, for a public node, every robot sharing it publicly):

* a node both robots migrated onto their own robot is nobody's shared instance;
* otherwise a different placement (one runs it in the cloud, the other on board, or
  in another container) or sharing mode (protected for one, public for the other, in
  one group) is a conflict, and so is any other aspect with a different value;
* a robot whose product lacks the node, or keeps it ``private``, asks nothing of the
  shared instance and never conflicts.

A conflict names the node and its instance, both robots, the values and, for each, the
feature and resolution element (``file:line:col``) that decided it.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Diagnostic, Location, ModelError, location_of
from spl.resolver.architecture.placement import (
    SHARED_ACROSS_USERS,
    Place,
    Placement,
    rapyuta_user,
)
from spl.resolver.fleets.asks import (
    AMBIGUOUS_SERVER,
    SERVER_INSTANCE,
    Ask,
    differences,
    scopes,
    shared_asks,
    shown,
)
from spl.resolver.fleets.fleet_file import Fleet, FleetRobot
from spl.resolver.resolution.context import describe
from spl.resolver.resolution.effects import (
    PLACEMENT,
    SHARING,
    Active,
    Aspect,
    Effect,
    LineEffects,
    NodeEffects,
    Settings,
    active_in,
)
from spl.resolver.resolution.engine import Resolution, resolve
from spl.resolver.resolution.product_line import ProductLine, load_product_line
from spl.resolver.resolution.product_selection import ProductSelection

if TYPE_CHECKING:
    from spl.metamodels import tsm_types
    from spl.resolver.architecture.product import ResolvedProduct

CONFLICT = "SPL040"
ROBOT_ID_TAKEN = "SPL041"


@dataclass
class RobotProduct:
    robot: FleetRobot
    resolution: Resolution

    @property
    def product(self) -> ResolvedProduct:
        return self.resolution.product


@dataclass
class FleetCheck:
    fleet: Fleet
    line: ProductLine
    effects: LineEffects
    robots: list[RobotProduct] = field(default_factory=list)
    asks: list[Ask] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not any(d.severity == "error" for d in self.diagnostics)

    def instances(self) -> dict[str, list[Ask]]:
        """Every shared cloud instance (by tag) and the robots' asks of its nodes."""
        found: dict[str, list[Ask]] = {}
        for ask in self.asks:
            if not ask.on_robot:
                found.setdefault(ask.tag, []).append(ask)
        return dict(sorted(found.items()))


def robot_selection(robot: FleetRobot, line: ProductLine) -> ProductSelection:
    """The robot's product selection with its robotIDs: the robot's name (``NAME_C`` for
    each robot container C when the line has several) unless ``deployment`` gives one."""
    selection = copy.copy(robot.selection)
    selection.deployment = {k: dict(v) for k, v in robot.selection.deployment.items()}
    robots = [c.name for c in line.tsm.containers if c.eClass.name == "RobotContainer"]
    for container in robots:
        settings = selection.deployment.setdefault(container, {})
        settings.setdefault(
            "robot_id", robot.name if len(robots) == 1 else f"{robot.name}_{container}"
        )
    return selection


def check_fleet(fleet: Fleet, line: ProductLine | None = None) -> FleetCheck:
    """Resolve every robot and compare what robots sharing an instance ask of it."""
    line = line or load_product_line(fleet.product_line)
    check = FleetCheck(fleet, line, LineEffects(line))
    # robotIDs aside, equal selections resolve alike (by what the selection decides)
    resolved: dict[tuple[object, ...], Resolution] = {}
    owners: dict[str, str] = {}
    places: dict[str, tuple[Place, str]] = {}  # instance tag -> (its place, first robot)
    robot_containers = {c.name for c in line.tsm.containers if c.eClass.name == "RobotContainer"}
    for robot in fleet.robots:
        selection = robot_selection(robot, line)
        for container, settings in sorted(selection.deployment.items()):
            if container not in robot_containers:  # resolve reports it: no such container
                continue
            taken = owners.setdefault(settings.get("robot_id", ""), robot.name)
            if taken != robot.name:
                check.diagnostics.append(
                    Diagnostic(
                        robot.location,
                        f"robot {robot.name}: robot_id {settings['robot_id']} of container "
                        f"{container} is already robot {taken}'s",
                        code=ROBOT_ID_TAKEN,
                    )
                )
        key = _resolution_key(selection)
        try:
            resolution = resolved.get(key) or resolve(line, selection)
        except ModelError as exc:
            check.diagnostics.extend(_about(robot, d) for d in exc.diagnostics)
            continue
        resolved[key] = resolution
        entry = RobotProduct(robot, resolution)
        check.robots.append(entry)
        check.diagnostics.extend(_about(robot, w) for w in resolution.product.warnings)
        errors: list[Diagnostic] = []
        placement = Placement(resolution.product.system, errors, group=robot.group)
        check.asks.extend(shared_asks(robot, resolution.product, placement))
        errors += _tags_taken(robot, selection, placement, places)
        check.diagnostics.extend(_about(robot, d) for d in errors)
    check.diagnostics.extend(find_conflicts(check))
    check.diagnostics.extend(users_apart(check))
    return check


def users_apart(check: FleetCheck) -> list[Diagnostic]:
    """A warning (SPL047) for each shared instance used by robots that log in as
    different Rapyuta users: the engine gives each user an instance of its own, so they
    share nothing on Rapyuta, while Kubernetes and Zenoh deploy one. At the first robot
    whose users differ from the first robot's. (Two users within one robot's product are
    that product's own warning.)"""
    users = {
        entry.robot.name: tuple(
            sorted({u for c in entry.product.system.containers if (u := rapyuta_user(c))})
        )
        for entry in check.robots
    }
    robots = {entry.robot.name: entry.robot for entry in check.robots}
    found = []
    for tag, asks in check.instances().items():
        using = [r for r in dict.fromkeys(a.robot for a in asks) if users[r]]
        other = next((r for r in using if users[r] != users[using[0]]), None)
        if other is None:
            continue
        who = ", ".join(f"{r} as {'/'.join(repr(u) for u in users[r])}" for r in using)
        found.append(
            Diagnostic(
                robots[other].location,
                f"robot {other}: shared instance {tag} is used by robots of different Rapyuta "
                f"users ({who}); the engine keeps each user's containers apart, so on "
                "Rapyuta they share nothing (kubernetes/ and zenoh/ deploy one instance): "
                "give these robots one user",
                "warning",
                SHARED_ACROSS_USERS,
            )
        )
    return found


def _about(robot: FleetRobot, diagnostic: Diagnostic) -> Diagnostic:
    """A robot's problem, at the robot's entry unless it is located in the fleet file
    itself (a rule of the line it breaks is named in the message)."""
    where, message = diagnostic.location, diagnostic.message
    entry = robot.location
    if entry is not None and (where is None or where.file != entry.file):
        if where is not None:
            message = f"{message} ({where})"
        where = entry
    return Diagnostic(where, f"robot {robot.name}: {message}", diagnostic.severity, diagnostic.code)


def _resolution_key(selection: ProductSelection) -> tuple[object, ...]:
    capabilities = selection.capabilities.source if selection.capabilities else None
    deployment = {
        c: {k: v for k, v in s.items() if k != "robot_id"} for c, s in selection.deployment.items()
    }
    return (
        tuple(selection.features),
        tuple(selection.deselected),
        repr(sorted(selection.sharing.items())),
        repr(sorted(selection.attributes.items())),
        capabilities,
        repr(sorted((c, sorted(s.items())) for c, s in deployment.items())),
    )


def _tags_taken(
    robot: FleetRobot,
    selection: ProductSelection,
    placement: Placement,
    places: dict[str, tuple[Place, str]],
) -> list[Diagnostic]:
    """Instances of ``robot`` whose tag another robot's different instance already has
    (a robotID or group equal to another group, a robotID, or ``public``): one Rapyuta tag
    and one Kubernetes name cannot be two instances. ``places`` collects every robot's.
    The placement may be of another robot's equal selection (robotIDs aside), so robot
    and private places are named with this robot's robotIDs."""
    ids = {
        container.endpoint.robotId: selection.deployment[container.name]["robot_id"]
        for container in placement.robots
        if container.endpoint is not None and container.name in selection.deployment
    }
    found = []
    own = [*placement.tags.values(), *(i.place for i in placement.cloud_instances())]
    for place in dict.fromkeys(own):
        if place.kind in ("robot", "private") and place.owner in ids:
            owner_id = ids[place.owner]
            tag = owner_id if place.kind == "robot" else f"{place.container}_{owner_id}"
            place = Place(tag, place.kind, place.container, owner_id)
        first, owner = places.setdefault(place.tag, (place, robot.name))
        if first != place:
            found.append(
                Diagnostic(
                    robot.location,
                    f"instance {place.tag} would be both {first.describe()} (robot {owner}) "
                    f"and {place.describe()}: rename the group or robot_id",
                )
            )
    return found


def find_conflicts(check: FleetCheck) -> list[Diagnostic]:
    """Every robot compared with the first robot that fixed each shared node in its scope."""
    products = {entry.robot.name: entry for entry in check.robots}
    first: dict[tuple, Ask] = {}
    found: dict[tuple, Diagnostic] = {}  # a pair compared in two scopes is reported once
    for ask in check.asks:
        for scope in scopes(ask):
            fixed = first.setdefault((ask.key, scope), ask)
            for aspect in differences(fixed, ask) if fixed is not ask else ():
                found.setdefault(
                    (fixed.robot, ask.robot, ask.key, aspect),
                    conflict(
                        check.effects,
                        products[fixed.robot],
                        fixed,
                        products[ask.robot],
                        ask,
                        aspect,
                    ),
                )
    return list(found.values())


def conflict(
    effects: LineEffects,
    first: RobotProduct,
    fixed: Ask,
    second: RobotProduct,
    ask: Ask,
    aspect: str,
) -> Diagnostic:
    node = effects.nodes[ask.key]
    differ = (
        f"robots {fixed.robot} and {ask.robot} ask for a different {aspect}: {fixed.robot} has "
        f"{shown(fixed, aspect)} ({why(effects, node, first, aspect)}), {ask.robot} has "
        f"{shown(ask, aspect)} ({why(effects, node, second, aspect)})"
    )
    if aspect.startswith(SERVER_INSTANCE):  # each product alone is fine, so a warning
        return Diagnostic(
            second.robot.location,
            f"shared node {ask.node} cannot call both servers: {differ}; the deployment "
            "connects its one instance to one of them, so give the server the node's sharing",
            "warning",
            AMBIGUOUS_SERVER,
        )
    return Diagnostic(
        second.robot.location, f"conflict on shared node {ask.node}: {differ}", code=CONFLICT
    )


def why(effects: LineEffects, node: NodeEffects, entry: RobotProduct, aspect: str) -> str:
    """The feature and resolution element that gave the robot's node this value."""
    active = active_in(set(entry.product.features))
    none = cast("Settings", None)  # a server is no function of a robot's settings
    if aspect.startswith(SERVER_INSTANCE):  # the server's sharing mode decides it
        value = node.servers[aspect.removeprefix(SERVER_INSTANCE)].value(active, none)
        server = cast("tsm_types.ServiceServer | None", value)
        server_node = effects.by_node.get(id(server.eContainer())) if server else None
        if server_node is None:
            return "the server's sharing mode"
        return (
            f"{server_node.name}'s sharing: {_decided(server_node.aspects[SHARING], active, entry)}"
        )
    if aspect.startswith("server of "):
        chosen = node.servers[aspect.removeprefix("server of ")]
        reason = _decided(chosen, active, entry)
        server = cast("tsm_types.ServiceServer | None", chosen.value(active, none))
        if server is not None:
            server_node = effects.by_node.get(id(server.eContainer()))
            if server_node is not None and not server_node.present(active):
                return f"{reason}; {server_node.name} is not in this product"
            moved = server_node.aspects[PLACEMENT].effective(active) if server_node else None
            if moved is not None and server_node is not None:  # moved: a node's
                reason += f"; {server_node.name} {_by(moved, entry, PLACEMENT)}"
        return reason
    return _decided(node.aspects[aspect], active, entry)


def _decided(aspect: Aspect, active: Active, entry: RobotProduct) -> str:
    effect = aspect.effective(active)
    if effect is None:
        return f"as the template has it ({aspect.default_where})"
    return _by(effect, entry, aspect.name)


def _by(effect: Effect, entry: RobotProduct, aspect: str) -> str:
    element = effect.element
    feature = element.feature.name
    text = f"{'migrated ' if aspect == PLACEMENT else ''}by feature {feature}: {describe(element)}"
    if aspect == SHARING:
        selection = entry.robot.selection
        if feature in selection.sharing:
            where = selection.location(f"sharing:{feature}")
            mode = selection.sharing[feature]
            return f"{text}, with the robot's sharing {feature}: {mode} ({where})"
        return f"{text}, the default sharing of {feature} ({location_of(element.feature.sharing)})"
    if effect.where is not None and effect.where != location_of(element):
        text += f" at {effect.where}"
    return text


def summary(check: FleetCheck) -> list[str]:
    """What ``spl fleet check`` prints on success: robots, groups and shared instances."""
    groups = sorted({entry.robot.group for entry in check.robots})
    instances = check.instances()
    lines = [
        f"fleet {check.fleet.name}: {len(check.robots)} robots in {len(groups)} "
        f"group{'s' if len(groups) != 1 else ''} ({', '.join(groups)}), "
        f"{len(instances)} shared cloud instance{'s' if len(instances) != 1 else ''}, no conflict"
    ]
    for tag, asks in instances.items():
        nodes = sorted({a.node for a in asks})
        robots = list(dict.fromkeys(a.robot for a in asks))
        mode = asks[0].mode
        scope = f"group {asks[0].group}" if mode == "protected" else "every group"
        lines.append(f"  {tag} ({mode}, {scope}): {', '.join(nodes)}; used by {', '.join(robots)}")
    return lines


def located(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    """Diagnostics in file order (robots' entries), as every command prints them."""
    return sorted(diagnostics, key=lambda d: (d.location or Location(""), d.message))
