"""What Zenoh bridges deliver, and whether any namespaces would deliver exactly the flow
table, worked out here on its own (docs/deployment.md, "How the bridges' namespaces are
chosen"), not with the generator's code.

A bridge routes each name of its allow lists under ``namespace + name``; two bridges (two
processes: a bridge never takes back its own data) exchange what one routes out and the
other routes in under one key. Read so, a set of bridges is *exact* for the crossings of
the flow table (by places and ROS names) when it delivers every crossing once and
nothing else, no place routes in through one bridge a name another of its bridges routes
out, and no called service or action key is served in two places.

:func:`brute_force` tries every choice of namespaces over the candidates the manual
names: for a robot's bridge, and for one end of a crossing between cloud instances (the
other end follows from the key), none or a robot's own ``/<robotID>``, each followed by
none or a rename prefix. Robots' choices are enumerated together; given them, crossings
whose names end in different segments never meet, so the cloud crossings are enumerated
per group of those.
"""

from __future__ import annotations

import itertools
import re
from collections import Counter, defaultdict
from dataclasses import dataclass

import json5

from spl.resolver.architecture.placement import Placement
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.wiring import Wiring

OUT = {"topic": "publishers", "service": "service_clients", "action": "action_clients"}
IN = {"topic": "subscribers", "service": "service_servers", "action": "action_servers"}
CALLED = ("service", "action")  # a key of these is answered by one place
Delivery = tuple[str, str, str, str, str]  # kind, source place, name, target place, name
VALID = re.compile(r"(/[A-Za-z][A-Za-z0-9_]*)*")


@dataclass(frozen=True)
class Bridge:
    place: str
    namespace: str
    lists: tuple[tuple[str, frozenset[str]], ...]  # (allow list, names)

    def names(self, allow: str) -> frozenset[str]:
        return dict(self.lists).get(allow, frozenset())


def written(files: dict) -> list[Bridge]:
    """The bridges of a ``zenoh/`` folder, read with a JSON5 reader."""
    found = []
    for path, data in sorted(files.items()):
        if not path.startswith("zenoh/") or not path.endswith(".json5"):
            continue
        place = path.removeprefix("zenoh/").removesuffix(".json5").split(".")[0]
        if place == "zenoh-router":
            continue
        plugin = json5.loads(data.decode("utf-8"))["plugins"]["ros2dds"]
        lists = tuple(sorted((k, frozenset(v)) for k, v in plugin["allow"].items()))
        found.append(Bridge(place, plugin.get("namespace", ""), lists))
    return found


def behaviour(bridges: list[Bridge]) -> tuple[Counter, set, set]:
    """Deliveries (counted: once per pair of bridges making it), echoes (place, name) and
    service keys served in two places for a caller."""
    delivered: Counter = Counter()
    for kind in OUT:
        for one, other in itertools.permutations(bridges, 2):
            for a in one.names(OUT[kind]):
                for b in other.names(IN[kind]):
                    if one.namespace + a == other.namespace + b:
                        delivered[(kind, one.place, a, other.place, b)] += 1
    echoes = set()
    for one, other in itertools.permutations(bridges, 2):
        if one.place == other.place:
            for kind in OUT:
                echoes |= {(one.place, n) for n in one.names(IN[kind]) & other.names(OUT[kind])}
    served = set()
    for kind in CALLED:
        servers, callers = defaultdict(set), set()
        for bridge in bridges:
            for name in bridge.names(IN[kind]):
                servers[bridge.namespace + name].add(bridge.place)
            callers |= {bridge.namespace + name for name in bridge.names(OUT[kind])}
        served |= {key for key in callers if len(servers[key]) > 1}
    return delivered, echoes, served


def exact(bridges: list[Bridge], crossings: set[Delivery]) -> bool:
    delivered, echoes, served = behaviour(bridges)
    return set(delivered) == crossings and set(delivered.values()) <= {1} and not (echoes or served)


@dataclass(frozen=True)
class Crossing:
    kind: str
    source: str  # place tag
    a: str  # ROS name at the source
    target: str
    b: str
    source_robot: str | None  # the robotID when the place is a robot
    target_robot: str | None

    @property
    def delivery(self) -> Delivery:
        return self.kind, self.source, self.a, self.target, self.b


def crossings(products: list[ResolvedProduct]) -> tuple[list[Crossing], list[str]]:
    """The flow table's crossings (the resolver's, from every robot's view) and robotIDs."""
    found: dict[Delivery, Crossing] = {}
    robots: list[str] = []
    for product in products:
        placement = Placement(product.system, [])
        wiring = Wiring(product.flows, placement, [])
        for robot in placement.robots:
            robots.append(placement.robot_ids[id(robot)])
            for c in wiring.crossings(robot):
                s = c.source.owner if c.source.is_robot else None
                t = c.target.owner if c.target.is_robot else None
                crossing = Crossing(  # the oracle's own words for the kind
                    str(c.kind), c.source.tag, c.source_name, c.target.tag, c.target_name, s, t
                )
                found.setdefault(crossing.delivery, crossing)
    return list(found.values()), list(dict.fromkeys(robots))


def _rest(key: str, name: str) -> str | None:
    """The namespace routing ``name`` under ``key``."""
    if not key.endswith(name):
        return None
    rest = key[: len(key) - len(name)]
    return rest if VALID.fullmatch(rest) else None


def candidates(table: list[Crossing], robots: list[str]) -> list[str]:
    renames = set()
    for c in table:
        for longer, shorter in ((c.a, c.b), (c.b, c.a)):
            rest = _rest(longer, shorter)
            if rest:
                renames.add(rest)
    own = ["/" + re.sub(r"[^A-Za-z0-9_]", "_", r) for r in robots]
    return list(dict.fromkeys(n + p for n in ["", *own] for p in ["", *sorted(renames)]))


def brute_force(table: list[Crossing], robots: list[str]) -> list[Bridge] | None:
    """Bridges of the first exact choice, or ``None`` when no choice is exact."""
    names = candidates(table, robots)
    wanted = {c.delivery for c in table}
    groups: dict[tuple[str, str], list[Crossing]] = defaultdict(list)
    for c in table:
        groups[(c.kind, c.b.rsplit("/", 1)[-1])].append(c)
    busy = sorted({r for c in table for r in (c.source_robot, c.target_robot) if r})
    for choice in itertools.product(names, repeat=len(busy)):
        spaces = dict(zip(busy, choice, strict=True))
        chosen: list[Bridge] = []
        for group in groups.values():
            found = _group(
                group, spaces, names, {d for d in wanted if d in {c.delivery for c in group}}
            )
            if found is None:
                break
            chosen += found
        else:
            merged = _bridges(
                [
                    (b.place, b.namespace, allow, n)
                    for b in chosen
                    for allow, ns in b.lists
                    for n in ns
                ]
            )
            if exact(merged, wanted):
                return merged
    return None


def _group(
    group: list[Crossing], spaces: dict[str, str], names: list[str], wanted: set
) -> list[Bridge] | None:
    """An exact choice for the cloud crossings of one group given the robots' namespaces."""
    fixed, free = [], []
    for c in group:
        if c.source_robot or c.target_robot:
            key = spaces[c.source_robot] + c.a if c.source_robot else spaces[c.target_robot] + c.b
            ends = (_rest(key, c.a), _rest(key, c.b))
            if None in ends or (c.target_robot and ends[1] != spaces[c.target_robot]):
                return None
            fixed.append((c, ends))
        else:
            options = []
            for n in names:
                for key in (n + c.a, n + c.b):
                    ends = (_rest(key, c.a), _rest(key, c.b))
                    if None not in ends and ends not in options:
                        options.append(ends)
            free.append((c, options))
    for choice in itertools.product(*(options for _, options in free)):
        entries = []
        for c, (first, second) in [*fixed, *zip((c for c, _ in free), choice, strict=True)]:
            entries.append((c.source, first, OUT[c.kind], c.a))
            entries.append((c.target, second, IN[c.kind], c.b))
        bridges = _bridges(entries)
        if exact(bridges, wanted):
            return bridges
    return None


def _bridges(entries: list[tuple[str, str, str, str]]) -> list[Bridge]:
    lists: dict[tuple[str, str], dict[str, set[str]]] = defaultdict(lambda: defaultdict(set))
    for place, namespace, allow, name in entries:
        lists[(place, namespace)][allow].add(name)
    return [
        Bridge(place, ns, tuple(sorted((k, frozenset(v)) for k, v in by.items())))
        for (place, ns), by in sorted(lists.items())
    ]


def space(table: list[Crossing], robots: list[str]) -> int:
    """How many choices :func:`brute_force` may try: the robots' together, times, for
    each, the choices of the cloud crossings of every group."""
    names = len(candidates(table, robots))
    busy = {r for c in table for r in (c.source_robot, c.target_robot) if r}
    clouds: Counter = Counter(
        (c.kind, c.b.rsplit("/", 1)[-1]) for c in table if not (c.source_robot or c.target_robot)
    )
    return names ** len(busy) * max(1, sum((2 * names) ** k for k in clouds.values()))
