"""Which zenoh-bridge-ros2dds bridge carries which crossing under which Zenoh key.

The crossings are :mod:`spl.resolver.architecture.wiring`'s: every flow whose two nodes run in
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
  bridge that prefix as namespace (``/harvester``) and the cloud end none.

That usual choice is kept wherever it carries the flow table exactly; where it does not
(a flow between two shared instances under no namespace meeting another place's bridge
under the same key, say), :mod:`spl.generators.transport.namespaces` searches the other
namespaces (a robot's, a rename prefix, both, or none, at either end) for an exact
choice. What no choice carries is reported (:attr:`Routes.problems`), never emitted: a
rename no namespace gives, a robot whose renames ask for two prefixes, and otherwise
what the usual choice would do wrong in the flow table's words: a subscriber that would
get a publisher's data a second time, or data (calls) the architecture does not deliver.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field

from spl.generators.transport.keys import Conflict, Entry, Link, prefix
from spl.generators.transport.namespaces import TRIES, Choice
from spl.metamodels.interface_kinds import FAMILIES, Family, side
from spl.resolver.architecture.wiring import Wiring

# zenoh-bridge-ros2dds's allow lists, each family's providing side's first (publishers,
# subscribers, service_servers, ...), as the registry names them (Family.zenoh_lists)
KINDS = tuple(side(family, first).zenoh_list for family in FAMILIES for first in (True, False))


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
    flows: set[tuple[Family, str, Bridge, Bridge]] = field(default_factory=set)  # kind, key, ...
    problems: list[str] = field(default_factory=list)


def links(wirings: list[Wiring]) -> tuple[list[Link], list[str]]:
    """The crossings of the wirings (one product's, or each robot's of a fleet) by places
    and ROS names, with the flows each carries, and every robotID, in model order."""
    found: dict[tuple[Family, str, str, str, str], Link] = {}
    robot_ids: list[str] = []
    for wiring in wirings:
        for robot in wiring.placement.robots:
            robot_ids.append(wiring.placement.robot_ids[id(robot)])
            for c in wiring.crossings(robot):
                key = (c.kind, c.source.tag, c.target.tag, c.source_name, c.target_name)
                link = found.setdefault(
                    key, Link(c.kind, c.source, c.target, c.source_name, c.target_name)
                )
                if all(flow is not c.flow for flow in link.flows):
                    link.flows.append(c.flow)
    return list(found.values()), list(dict.fromkeys(robot_ids))


def routes(wirings: list[Wiring], limit: int = TRIES) -> Routes:
    """Every crossing of the wirings given to the bridges that carry it, under the
    namespaces :class:`~spl.generators.transport.namespaces.Choice` finds exact (trying at
    most ``limit`` choices)."""
    found = Routes()
    table, robot_ids = links(wirings)
    found.problems = _impossible(table, robot_ids)
    if found.problems:
        return found
    choice = Choice(table, robot_ids, limit)
    conflicts = choice.choose()
    if conflicts:
        delivered = {(id(f.source), id(f.target)) for w in wirings for f in w.flows}
        words = _Words(table, choice.usual_keys, delivered)
        found.problems = sorted({words.problem(conflict) for conflict in conflicts})
        if choice.gave_up:
            found.problems.append(
                f"no exact choice of bridge namespaces was found in {limit} tries"
            )
        return found
    found.robot_namespaces = dict(choice.namespaces)
    for index, key in sorted(choice.keys.items()):
        link = table[index]
        out_list, in_list = link.kind.zenoh_lists
        source_ns, target_ns = prefix(key, link.source_name), prefix(key, link.target_name)
        assert source_ns is not None and target_ns is not None  # the choice's keys fit
        source, target = Bridge(link.source.tag, source_ns), Bridge(link.target.tag, target_ns)
        found.lists[source][out_list].add(link.source_name)
        found.lists[target][in_list].add(link.target_name)
        found.flows.add((link.kind, key, source, target))
    return found


def _impossible(table: list[Link], robot_ids: list[str]) -> list[str]:
    """What no namespace gives: a rename other than by a prefix, a robot whose renames
    ask for prefixes neither of which ends the other (its one bridge has one namespace)."""
    problems = []
    for link in table:
        if link.longest() is None:
            problems.append(_apart(link))
    choice = Choice(table, robot_ids)
    for robot in robot_ids:
        wanted = choice.wanted(robot)
        longest_prefix = max(wanted, key=len, default="")
        if any(not longest_prefix.endswith(p) for p in wanted):
            problems.append(
                f"the renames at robot {robot} need the bridge namespaces "
                f"{' and '.join(sorted(wanted))}, and a bridge has one"
            )
    return sorted(set(problems))


def _apart(link: Link) -> str:
    flow = link.flows[0]
    both = link.source.is_robot and link.target.is_robot
    return (
        f"the {link.kind} {link.source_name} of {link.source.tag} arrives in {link.target.tag} "
        f"as {link.target_name} ({_end(flow.source)} -> {_end(flow.target)}), which no bridge "
        "namespace gives" + (": each robot's bridge has its own" if both else "")
    )


class _Words:
    """A conflict of the usual choice in the flow table's words."""

    def __init__(self, table: list[Link], keys: dict[int, str], delivered: set) -> None:
        self.delivered = delivered
        self.at: dict[Entry, list] = defaultdict(list)  # the flows behind each entry
        for index, key in keys.items():
            for entry in table[index].ends(key) or ():
                self.at[entry] += table[index].flows

    def problem(self, conflict: Conflict) -> str:
        first, second = conflict.first, conflict.second
        if conflict.link is not None or first is None or second is None:
            assert conflict.link is not None
            return _apart(conflict.link)
        kind, key = first[0], first[3] + first[4]
        if conflict.what == "served":
            callers = [
                e for e in self.at if not e[0].on_topic and e[1] == "out" and e[3] + e[4] == key
            ]
            reach = "; ".join(self.effect(c, s) for c in callers[:1] for s in (first, second))
            return f"the service key {key} is served by {first[2]} and {second[2]}: {reach}"
        if conflict.what == "echo":
            return (
                f"in {first[2]}, {first[4]} comes in through the bridge of namespace "
                f"'{first[3] or '/'}' and would leave again through the one of "
                f"'{second[3] or '/'}': " + self.effect(first, second)
            )
        because = (
            "which the architecture does not connect"
            if conflict.what == "unconnected"
            else "which another pair of bridges carries already"
        )
        return (
            f"zenoh would carry the {kind} key {key} from {first[2]} to {second[2]}, "
            f"{because}: " + self.effect(first, second)
        )

    def effect(self, origin: Entry, destination: Entry) -> str:
        """What would happen if what the flows at entry ``origin`` carry went on to the
        consumers of the flows at ``destination``: a subscriber getting a publisher's data
        twice, or data (calls) the architecture does not deliver there."""
        phrases = []
        for before in self.at.get(origin, ()):
            for after in self.at.get(destination, ()):
                source, target = before.source, after.target
                again = (id(source), id(target)) in self.delivered
                if not before.kind.on_topic:
                    phrases.append(
                        f"the calls of {_end(source)} could reach {_end(target)}"
                        + ("" if again else ", which the architecture does not connect")
                    )
                else:
                    phrases.append(
                        f"{_end(target)} would get the data of {_end(source)} "
                        + ("a second time" if again else "that the architecture does not deliver")
                    )
        phrases = list(dict.fromkeys(phrases))
        if len(phrases) > 3:
            phrases = [*phrases[:3], f"and {len(phrases) - 3} more"]
        return "; ".join(phrases) or "data the architecture does not deliver"


def _end(interface) -> str:
    """A node interface as ``Container.Node.interface``."""
    node = interface.eContainer()
    return f"{node.eContainer().name}.{node.name}.{interface.name}"
