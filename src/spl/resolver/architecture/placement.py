"""Where each node of a resolved architecture runs, by sharing mode (docs/deployment.md).

A TSM cloud container ``C`` is a template: deployed, it becomes up to three instances,
by the sharing mode of its nodes:

=============  =====================  ==========================================
mode           tag                    instances
=============  =====================  ==========================================
private        ``<C>_<robotID>``      one per robot using ``C``
protected      ``<C>_<group>``        one per group (``group`` = C's group, else
                                      C's name)
public         ``<C>_public``         one for everybody
=============  =====================  ==========================================

Nodes of a robot container run on that robot (tag: its robotID). Two robots whose
nodes get the same tag share one instance: this is the rule both the Rapyuta
generator (which names containers by it) and the fleet analysis (which checks that
robots sharing an instance ask the same of it) apply, so it lives here, once.

A robot *uses* ``C`` when endpoint connections link the two, directly or through other
cloud containers (robots never relay for each other). Of ``C``'s private nodes, a robot
gets an instance only of those it can feed or be fed by through the flow table
(:mod:`spl.resolver.architecture.private_instances`); a private partition left with no node is not
deployed for that robot.
"""

from __future__ import annotations

import re
from collections import defaultdict
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple, cast

from spl.core.diagnostics import Diagnostic, location_of
from spl.metamodels import tsm
from spl.resolver.architecture.flows import FlowTable
from spl.resolver.architecture.private_instances import PrivateInstances

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

TAG = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_-]*")
MODES = ("private", "protected", "public")
SHARED_MODES = ("protected", "public")


@dataclass(frozen=True, order=True)
class Place:
    """A deployed instance: a robot, or one sharing partition of a TSM cloud container."""

    tag: str  # the robotID or the container instance's tag
    kind: str  # "robot" or a sharing mode
    container: str  # the TSM container whose ROS graph this is (a partition of it)
    owner: str  # robotID (robot, private), group (protected) or "public"

    @property
    def is_robot(self) -> bool:
        return self.kind == "robot"

    @property
    def shared(self) -> bool:
        return self.kind in SHARED_MODES

    def describe(self) -> str:
        if self.is_robot:
            return f"robot container {self.container}"
        return f"the {self.kind} partition of {self.container}"


class Instance(NamedTuple):
    """A cloud instance as deployed: its place, the TSM container it partitions, the
    nodes it runs (in model order) and the robotIDs using it (in model order)."""

    place: Place
    container: tsm_types.CloudContainer
    nodes: tuple[tsm_types.Node, ...]
    robots: tuple[str, ...]


def sharing_mode(node: tsm_types.Node) -> str:
    """A node's sharing mode (``private`` when the model leaves it unset)."""
    return node.sharing.name if node.sharing is not None else "private"


def container_of(interface: tsm_types.Interface | None) -> tsm_types.Container | None:
    """The container of an endpoint interface or of a node interface."""
    owner = interface.eContainer() if interface is not None else None
    return owner.eContainer() if owner is not None else None


def links(system: tsm_types.System) -> defaultdict[int, set[int]]:
    """The containers (by ``id``) each container exchanges data with through endpoint
    connections, in both directions."""
    neighbours: defaultdict[int, set[int]] = defaultdict(set)
    for connection in system.connections:
        a, b = container_of(connection.source), container_of(connection.target)
        if a is not None and b is not None and a is not b:
            neighbours[id(a)].add(id(b))
            neighbours[id(b)].add(id(a))
    return neighbours


def rapyuta_user(container: tsm_types.Container) -> str | None:
    """The Rapyuta user a robot container logs in as (None: a cloud container, or none
    given)."""
    endpoint = container.endpoint if container.eClass.name == "RobotContainer" else None
    return endpoint.user if endpoint is not None and endpoint.user else None


class Placement:
    """Where each node runs in the instance of one resolved system seen from each robot.

    Problems (a robot_id or group that is no valid tag, two instances that would get
    one tag) are appended to ``errors``, located in the model.
    """

    def __init__(
        self,
        system: tsm_types.System,
        errors: list[Diagnostic],
        group: str | None = None,
        flows: FlowTable | None = None,
    ) -> None:
        """``group``, when given, is the group of every cloud container: a fleet robot's
        group, which decides whose protected instances it shares. ``flows`` is the
        system's flow table (``ResolvedProduct.flows``), computed when first needed if
        not given: it decides which private instances each robot gets."""
        T = tsm()
        self._flows = flows
        self._private: PrivateInstances | None = None
        # (id(container), mode, id(robot) for a private place) -> the place (_locate)
        self._located: dict[tuple[int, str, int], Place] = {}
        self.T = T
        self.system = system
        self.errors = errors
        self.robots: list[tsm_types.Container] = [
            c for c in system.containers if isinstance(c, T.RobotContainer)
        ]
        self.robot_ids = {id(r): self._robot_id(r) for r in self.robots}
        self.groups = {
            id(c): self._group(c, group)
            for c in system.containers
            if isinstance(c, T.CloudContainer)
        }
        self.neighbours = links(system)
        self.by_id = {id(c): c for c in system.containers}
        self.tags: dict[str, Place] = {}
        self.folded_tags: dict[str, Place] = {}  # by tag in lower case
        self.clashes: list[Diagnostic] = []  # the tag clashes among ``errors``
        for robot in self.robots:  # robots first: a container tag may not take their ids
            self.place(robot, "private", robot)

    def _robot_id(self, robot: tsm_types.Container) -> str:
        robot_id = robot.endpoint.robotId if robot.endpoint is not None else None
        if not robot_id or not TAG.fullmatch(robot_id):
            problem = (
                f"robot_id {robot_id!r} is not a Rapyuta tag (letters, digits, '_' and '-')"
                if robot_id
                else 'no robot_id: give the robot\'s endpoint one (endpoint robot_id "...") '
                "or set it in the selection's deployment"
            )
            self.errors.append(
                Diagnostic(
                    location_of(robot.endpoint) or location_of(robot),
                    f"robot container {robot.name}: {problem}",
                )
            )
            return robot.name
        return robot_id

    def _group(self, cloud: tsm_types.CloudContainer, group: str | None) -> str:
        group = group or cloud.group or cloud.name
        if not TAG.fullmatch(group):
            self.errors.append(
                Diagnostic(
                    location_of(cloud),
                    f"cloud container {cloud.name}: group {group!r} is not a Rapyuta tag "
                    "(letters, digits, '_' and '-')",
                )
            )
            return cloud.name
        return group

    def is_robot(self, container: tsm_types.Container) -> bool:
        return isinstance(container, self.T.RobotContainer)

    def scope(self, robot: tsm_types.Container) -> list[tsm_types.CloudContainer]:
        """The cloud containers ``robot`` uses: linked directly or through other clouds."""
        seen: set[int] = set()
        frontier = [id(robot)]
        while frontier:
            current = frontier.pop()
            for neighbour in self.neighbours[current]:
                if neighbour not in seen and not self.is_robot(self.by_id[neighbour]):
                    seen.add(neighbour)
                    frontier.append(neighbour)
        clouds = [self.by_id[i] for i in sorted(seen, key=lambda i: self.by_id[i].name)]
        return cast("list[tsm_types.CloudContainer]", clouds)  # no robot relays

    def view(self, robot: tsm_types.Container) -> list[tsm_types.Container]:
        """The containers ``robot``'s deployment sees: itself, the clouds it uses and the
        robots linked to those."""
        allowed = {id(robot)} | {id(c) for c in self.scope(robot)}
        for container_id in list(allowed):
            allowed |= {n for n in self.neighbours[container_id] if self.is_robot(self.by_id[n])}
        return [c for c in self.by_id.values() if id(c) in allowed]

    @property
    def flows(self) -> FlowTable:
        if self._flows is None:
            self._flows = FlowTable.of(self.system)
        return self._flows

    @property
    def private(self) -> PrivateInstances:
        """Which private instances each robot gets and why (docs/deployment.md, "Private
        instances"), decided once per placement, on first use."""
        if self._private is None:
            self._private = PrivateInstances(self, self.flows)
        return self._private

    def deploys(self, node: tsm_types.Node, robot: tsm_types.Container) -> bool:
        """Whether ``node`` runs in ``robot``'s deployment: a robot's or shared node
        always, a private one when the robot gets its instance."""
        if sharing_mode(node) != "private" or self.is_robot(node.eContainer()):
            return True
        return self.private.reason(node, robot) is not None

    def place(
        self,
        container: tsm_types.Container,
        mode: str,
        robot: tsm_types.Container | None,
        claim: bool = True,
    ) -> Place:
        # (``robot`` None: seen from no robot in particular, for a node that is not private)
        """The instance of ``container`` holding its ``mode`` nodes, as ``robot`` sees it;
        ``claim``: its tag is taken (checked against every other tag taken), as it is by
        every instance deployed, not by one merely asked about."""
        place = self._locate(container, mode, robot)
        if not claim:
            return place
        known = self.tags.setdefault(place.tag, place)
        twin = self.folded_tags.setdefault(place.tag.lower(), place)
        if twin.tag != place.tag:  # files are named after tags (zenoh/<robot_id>.json5)
            self._clash(
                container,
                f"Rapyuta tags {twin.tag!r} ({twin.describe()}) and {place.tag!r} "
                f"({place.describe()}) differ only in case: their bundle files would be "
                "one file on a case-insensitive file system; rename one",
            )
        if known != place:
            self._clash(
                container,
                f"Rapyuta tag {place.tag!r} would name both {known.describe()} and "
                f"{place.describe()}: rename a container, group or robot_id",
            )
        return place

    def _locate(
        self, container: tsm_types.Container, mode: str, robot: tsm_types.Container | None
    ) -> Place:
        """The place :meth:`place` names, made once per container, mode and robot (every
        output asks again for each flow it places)."""
        is_robot = self.is_robot(container)
        key = (id(container), "robot" if is_robot else mode, id(robot) if mode == "private" else 0)
        place = self._located.get(key)
        if place is not None:
            return place
        if is_robot:
            robot_id = self.robot_ids[id(container)]
            place = Place(robot_id, "robot", container.name, robot_id)
        elif mode == "private":
            robot_id = self.robot_ids[id(robot)]
            place = Place(f"{container.name}_{robot_id}", mode, container.name, robot_id)
        elif mode == "protected":
            group = self.groups[id(container)]
            place = Place(f"{container.name}_{group}", mode, container.name, group)
        else:
            place = Place(f"{container.name}_public", mode, container.name, "public")
        self._located[key] = place
        return place

    def _clash(self, container: tsm_types.Container, message: str) -> None:
        clash = Diagnostic(location_of(container), message)
        self.errors.append(clash)
        self.clashes.append(clash)

    def partitions(
        self, robot: tsm_types.Container, modes: tuple[str, ...] = MODES
    ) -> list[Instance]:
        """The cloud instances ``robot`` uses, by container (by name) and sharing mode:
        its private ones holding the private nodes it gets (none: not deployed), the
        shared ones whole; of the sharing ``modes`` only."""
        robot_id = self.robot_ids[id(robot)]
        found = []
        for cloud in self.scope(robot):
            by_mode: dict[str, list[tsm_types.Node]] = {mode: [] for mode in modes}
            for node in cloud.nodes:  # each node's mode read once
                held = by_mode.get(sharing_mode(node))
                if held is not None and self.deploys(node, robot):
                    held.append(node)
            for mode, nodes in by_mode.items():
                if nodes:
                    place = self.place(cloud, mode, robot)
                    found.append(Instance(place, cloud, tuple(nodes), (robot_id,)))
        return found

    def cloud_instances(self, modes: tuple[str, ...] = MODES) -> list[Instance]:
        """Every deployed cloud instance once, with its nodes, ordered by tag: the
        partitions robots use (a shared one is listed once, with every robot using it);
        of the sharing ``modes`` only."""
        found: dict[str, Instance] = {}
        for robot in self.robots:
            for instance in self.partitions(robot, modes):
                known = found.setdefault(instance.place.tag, instance._replace(robots=()))
                found[instance.place.tag] = known._replace(robots=(*known.robots, *instance.robots))
        return [found[tag] for tag in sorted(found)]

    def node_place(
        self, node: tsm_types.Node, robot: tsm_types.Container | None, claim: bool = True
    ) -> Place:
        """The instance ``node`` runs in for ``robot`` (``claim``: as :meth:`place`)."""
        return self.place(node.eContainer(), sharing_mode(node), robot, claim)


SHARED_ACROSS_USERS = "SPL047"
