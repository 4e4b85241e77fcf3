"""Which zenoh-bridge-ros2dds bridge carries which crossing under which Zenoh key.

The crossings are :mod:`spl.resolver.wiring`'s: every flow whose two nodes run in
different places (a robot, or one instance of a cloud container), from every robot's
view, once each. A bridge routes a local ROS name ``n`` under the Zenoh key ``N + n``,
``N`` being the bridge's ``namespace`` (DEFAULT_CONFIG.json5: "added to all discovered
interfaces when routed to Zenoh"); two bridges exchange data when their keys are equal.
So namespaces do two jobs here:

- **Isolation.** Every robot's bridge has a namespace of its own, ``/<robotID>`` (``-``
  written ``_``), and so has each bridge that talks with it: a cloud instance gets one
  bridge per robot it exchanges data with. Two robots publishing ``/camera/rgb/image``
  for their own private instances never see each other's images; a shared instance
  receives each robot's data through that robot's bridge, as the Rapyuta bridges give it.
  Flows between two cloud instances take the namespace of the robot a private end
  belongs to, or none between two shared instances.
- **Renaming.** A bridge that renames a topic by a prefix (``/camera/image_raw`` on the
  robot, ``/harvester/camera/image_raw`` in the cloud) is carried by giving the robot's
  bridge that prefix as namespace (``/harvester``) and the cloud end none. All renames
  of one robot must agree on the prefix; a rename that is not a prefix cannot be carried.

What cannot be carried is reported (:attr:`Routes.problems`), never emitted: a rename
no namespace gives, two places whose bridges would exchange data the architecture does
not connect (one key produced or served in several places for consumers wired to only
one of them), or a place where one bridge would route out what another bridge of the
same place routes in (the second would forward the first's data). Each problem says
what it would do to the flow table's flows: a subscriber that would get a publisher's
data a second time, or data the architecture does not deliver to it.
"""

from __future__ import annotations

import re
from collections import defaultdict
from dataclasses import dataclass, field
from typing import cast

from spl.resolver.flows import Flow
from spl.resolver.placement import Place
from spl.resolver.wiring import Wiring

KINDS = (
    "publishers",
    "subscribers",
    "service_servers",
    "service_clients",
    "action_servers",
    "action_clients",
)
NAMESPACE = re.compile(r"(/[A-Za-z][A-Za-z0-9_]*)+")
# per crossing kind: the allow list at the source, and at the target
_LISTS = {"topic": ("publishers", "subscribers"), "service": ("service_clients", "service_servers")}


@dataclass(frozen=True, order=True)
class Bridge:
    """One zenoh-bridge-ros2dds process: a place and its namespace ("" for none)."""

    place: str
    namespace: str


@dataclass
class Routes:
    """The allow lists of every bridge, the robots' namespaces, or what cannot be carried."""

    lists: dict[Bridge, dict[str, set[str]]] = field(
        default_factory=lambda: defaultdict(lambda: {kind: set() for kind in KINDS})
    )
    robot_namespaces: dict[str, str] = field(default_factory=dict)  # robotID -> namespace
    flows: set[tuple[str, str, Bridge, Bridge]] = field(default_factory=set)  # kind, key, ...
    problems: list[str] = field(default_factory=list)
    # the table's flows behind each allow-list entry, by (bridge, list, ROS name)
    carried: dict[tuple[Bridge, str, str], list[Flow]] = field(
        default_factory=lambda: defaultdict(list)
    )
    delivered: set[tuple[int, int]] = field(default_factory=set)  # (source, target) ids

    def effect(self, origin: tuple[Bridge, str, str], destination: tuple[Bridge, str, str]) -> str:
        """What would happen if what the flows at allow-list entry ``origin`` carry went on
        to the consumers of the flows at ``destination``, in the flow table's words: a
        subscriber getting a publisher's data twice, or data (calls) the architecture
        does not deliver there."""
        pairs = [
            (before.source, after.target, before.kind)
            for before in self.carried.get(origin, ())
            for after in self.carried.get(destination, ())
        ]
        phrases = []
        for source, target, kind in dict.fromkeys(pairs):
            again = (id(source), id(target)) in self.delivered
            if kind == "service":
                phrases.append(
                    f"the calls of {_end(source)} could reach {_end(target)}"
                    + ("" if again else ", which the architecture does not connect")
                )
            else:
                phrases.append(
                    f"{_end(target)} would get the data of {_end(source)} "
                    + ("a second time" if again else "that the architecture does not deliver")
                )
        if len(phrases) > 3:
            phrases = [*phrases[:3], f"and {len(phrases) - 3} more"]
        return "; ".join(phrases) or "data the architecture does not deliver"


def _prefix(key: str, name: str) -> str | None:
    """The namespace a bridge needs to route ``name`` under ``key``, if one can."""
    if not key.endswith(name):
        return None
    prefix = key[: len(key) - len(name)]
    return prefix if prefix == "" or NAMESPACE.fullmatch(prefix) else None


def _robot_namespaces(robot_ids: list[str], crossings: list, routes: Routes) -> None:
    """``/<robotID>``, or the one prefix every rename at the robot asks for."""
    for robot_id in robot_ids:
        wanted = set()
        for c in crossings:
            if c.source_name == c.target_name:
                continue
            if c.source.is_robot and c.source.owner == robot_id:
                wanted.add(_prefix(c.target_name, c.source_name))
            if c.target.is_robot and c.target.owner == robot_id:
                wanted.add(_prefix(c.source_name, c.target_name))
        wanted.discard(None)  # reported with the crossing
        namespaces = cast("set[str]", wanted)
        if len(namespaces) > 1:
            routes.problems.append(
                f"the renames at robot {robot_id} need the bridge namespaces "
                f"{' and '.join(sorted(namespaces))}, and a bridge has one"
            )
        default = "/" + re.sub(r"[^A-Za-z0-9_]", "_", robot_id)
        routes.robot_namespaces[robot_id] = min(namespaces) if namespaces else default


def _ends(routes: Routes, source: Place, target: Place, a: str, b: str) -> tuple | None:
    """The namespaces of the two bridges carrying a flow from ``a`` at ``source`` to
    ``b`` at ``target``, and its key; ``None`` when no namespaces can. The end that
    belongs to a robot (the robot, or its private instance) takes that robot's
    namespace; the other end the one that makes the keys equal."""
    spaces = routes.robot_namespaces
    first: str | None
    second: str | None
    if source.is_robot or (not target.is_robot and source.kind == "private"):
        first = spaces[source.owner]
        key = first + a
        second = _prefix(key, b)
        if second is None or (target.is_robot and second != spaces[target.owner]):
            return None
        return first, second, key
    second = spaces[target.owner] if target.is_robot or target.kind == "private" else ""
    key = second + b
    first = _prefix(key, a)
    return None if first is None else (first, second, key)


def routes(wirings: list[Wiring]) -> Routes:
    """Every crossing of the wirings (one product's, or each robot's of a fleet) given
    to the bridges that carry it, then checked together."""
    found = Routes()
    crossings, seen, robot_ids = [], set(), []
    for wiring in wirings:
        found.delivered |= {(id(f.source), id(f.target)) for f in wiring.flows}
        for robot in wiring.placement.robots:
            robot_ids.append(wiring.placement.robot_ids[id(robot)])
            for c in wiring.crossings(robot):
                key = (c.kind, c.source.tag, c.target.tag, c.source_name, c.target_name)
                if key not in seen:
                    seen.add(key)
                    crossings.append(c)
    _robot_namespaces(list(dict.fromkeys(robot_ids)), crossings, found)
    for c in crossings:
        ends = _ends(found, c.source, c.target, c.source_name, c.target_name)
        if ends is None or (c.source.is_robot and c.target.is_robot):
            found.problems.append(
                f"the {c.kind} {c.source_name} of {c.source.tag} arrives in {c.target.tag} "
                f"as {c.target_name} ({_end(c.flow.source)} -> {_end(c.flow.target)}), which "
                "no bridge namespace gives"
                + (
                    ": each robot's bridge has its own"
                    if c.source.is_robot and c.target.is_robot
                    else ""
                )
            )
            continue
        out_list, in_list = _LISTS[c.kind]
        source, target = Bridge(c.source.tag, ends[0]), Bridge(c.target.tag, ends[1])
        found.lists[source][out_list].add(c.source_name)
        found.lists[target][in_list].add(c.target_name)
        found.flows.add((c.kind, ends[2], source, target))
        found.carried[(source, out_list, c.source_name)].append(c.flow)
        found.carried[(target, in_list, c.target_name)].append(c.flow)
    if not found.problems:
        found.problems += _unconnected(found) + _echoes(found)
    found.problems = sorted(set(found.problems))
    return found


def _unconnected(found: Routes) -> list[str]:
    """Exchanges of equal keys the architecture does not connect."""
    problems = []
    for kind, (out_list, in_list) in _LISTS.items():
        sources, targets = defaultdict(set), defaultdict(set)
        for bridge, lists in found.lists.items():
            for name in lists[out_list]:
                sources[bridge.namespace + name].add(bridge)
            for name in lists[in_list]:
                targets[bridge.namespace + name].add(bridge)
        for key in sorted(sources.keys() & targets.keys()):
            if kind == "service" and len({t.place for t in targets[key]}) > 1:
                places = " and ".join(sorted({t.place for t in targets[key]}))
                problems.append(f"the service key {key} is served by {places}")
            for source in sorted(sources[key]):
                for target in sorted(targets[key]):
                    wired = (kind, key, source, target) in found.flows
                    if source.place != target.place and not wired:
                        out = (source, out_list, key.removeprefix(source.namespace))
                        into = (target, in_list, key.removeprefix(target.namespace))
                        problems.append(
                            f"zenoh would carry the {kind} key {key} from {source.place} to "
                            f"{target.place}, which the architecture does not connect: "
                            + found.effect(out, into)
                        )
    return problems


def _echoes(found: Routes) -> list[str]:
    """Names one bridge of a place routes in and another routes out."""
    problems = []
    by_place: dict[str, list[Bridge]] = defaultdict(list)
    for bridge in found.lists:
        by_place[bridge.place].append(bridge)
    for place, bridges in sorted(by_place.items()):
        for one in bridges:
            for other in bridges:
                if one == other:
                    continue
                for out_list, in_list in _LISTS.values():
                    both = found.lists[one][in_list] & found.lists[other][out_list]
                    for name in sorted(both):
                        problems.append(
                            f"in {place}, {name} comes in through the bridge of namespace "
                            f"'{one.namespace or '/'}' and would leave again through the one "
                            f"of '{other.namespace or '/'}': "
                            + found.effect((one, in_list, name), (other, out_list, name))
                        )
    return problems


def _end(interface) -> str:
    """A node interface as ``Container.Node.interface``."""
    node = interface.eContainer()
    return f"{node.eContainer().name}.{node.name}.{interface.name}"
