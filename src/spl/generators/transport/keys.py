"""The Zenoh keys of the links between places, and what a choice of them does wrong
(docs/deployment.md, "How the bridges' namespaces are chosen").

A bridge routes a local ROS name ``n`` under the Zenoh key ``N + n``, ``N`` its namespace;
two bridges exchange data when their keys are equal. A bridge never takes back what it
sent itself (zenoh-bridge-ros2dds subscribes to remote publications only, and its DDS
writers ignore its own readers), but two bridges of one place are two processes. So each
:class:`Link` (a crossing of the flow table between two places, by ROS names) is given a
key, and its two bridges and allow-list entries follow from it. A choice of keys is
*exact* when the bridges deliver the links and nothing else:

- no two bridges exchange under equal keys what the table does not connect (*unconnected*);
- no link is delivered by two pairs of bridges (*twice*);
- no place routes in through one bridge a name another of its bridges routes out: the
  second would forward the first's data (*echo*);
- no service key called from somewhere is served in two places (a call reaches one).

Each of these is a pair of entries (or a key's entries) that, once present, stays wrong
whatever else is added; :class:`KeySpace` counts them as entries come and go, so a search
can try a choice and take it back.
"""

from __future__ import annotations

import re
from collections import defaultdict
from dataclasses import dataclass, field

from spl.metamodels.interface_kinds import Family
from spl.resolver.architecture.flows import Flow
from spl.resolver.architecture.placement import Place

NAMESPACE = re.compile(r"(/[A-Za-z][A-Za-z0-9_]*)+")
Delivery = tuple[Family, str, str, str, str]  # kind, source place, its name, target place, its name
Entry = tuple[Family, str, str, str, str]  # kind, "out" | "in", place, namespace, ROS name
Token = tuple[Family, str]  # kind, last segment of a ROS name: entries of other tokens never meet


def prefix(key: str, name: str) -> str | None:
    """The namespace a bridge needs to route ``name`` under ``key``, if one can."""
    if not key.endswith(name):
        return None
    rest = key[: len(key) - len(name)]
    return rest if rest == "" or NAMESPACE.fullmatch(rest) else None


def robot_namespace(robot_id: str) -> str:
    """A robot's own namespace, ``/<robotID>`` with every other character written ``_``."""
    return "/" + re.sub(r"[^A-Za-z0-9_]", "_", robot_id)


def token(kind: Family, name: str) -> Token:
    return kind, name.rsplit("/", 1)[-1]


@dataclass(eq=False)
class Link:
    """The flows of the table from one ROS name of a place to one of another (or the same
    place under another name): what one pair of bridges carries under one key."""

    kind: Family
    source: Place
    target: Place
    source_name: str
    target_name: str
    flows: list[Flow] = field(default_factory=list)

    @property
    def delivery(self) -> Delivery:
        return self.kind, self.source.tag, self.source_name, self.target.tag, self.target_name

    @property
    def robots(self) -> list[str]:
        return list(dict.fromkeys(p.owner for p in (self.source, self.target) if p.is_robot))

    def longest(self) -> str | None:
        """The longer of the two names when the other ends it; every key ends with it."""
        a, b = sorted((self.source_name, self.target_name), key=len)
        return b if prefix(b, a) is not None else None

    def ends(self, key: str) -> tuple[Entry, Entry] | None:
        """The entries of the source's and the target's bridge carrying it under ``key``."""
        first, second = prefix(key, self.source_name), prefix(key, self.target_name)
        if first is None or second is None:
            return None
        return (
            (self.kind, "out", self.source.tag, first, self.source_name),
            (self.kind, "in", self.target.tag, second, self.target_name),
        )


@dataclass(frozen=True)
class Conflict:
    """Why a choice is not exact: ``what`` is "unconnected", "twice", "echo" or "served"
    (entries ``first`` and ``second``: out and in, in and out, two servers), or "apart"
    (the link ``link`` has no key the namespaces of its robots' bridges give)."""

    what: str
    first: Entry | None = None
    second: Entry | None = None
    link: Link | None = None
    involved: tuple[Entry, ...] = ()  # every entry without which it would not be

    def tokens(self) -> set[Token]:
        if self.link is not None:
            return {
                token(self.link.kind, n) for n in (self.link.source_name, self.link.target_name)
            }
        return {token(e[0], e[4]) for e in (self.first, self.second) if e is not None}


class KeySpace:
    """The entries of every bridge's allow lists, and how many wrongs they make together."""

    def __init__(self, wanted: set[Delivery]) -> None:
        self.wanted = wanted
        self.count: dict[Entry, int] = defaultdict(int)
        self.by_key: dict[tuple[Family, str, str], set[Entry]] = defaultdict(set)
        self.by_name: dict[tuple[Family, str, str, str], set[str]] = defaultdict(set)
        self.pairs: dict[Delivery, set[tuple[Entry, Entry]]] = defaultdict(set)
        self.bad = 0

    def add(self, link: Link, key: str) -> list[Conflict]:
        """The link's two entries under ``key`` (``key`` must be one of its keys), and the
        wrongs they make with the entries already there."""
        found: list[Conflict] = []
        for entry in link.ends(key) or ():
            self.count[entry] += 1
            if self.count[entry] == 1:
                found += self._meet(entry)
                served = self._served(entry)
                self.by_key[(entry[0], entry[1], entry[3] + entry[4])].add(entry)
                self.by_name[(entry[0], entry[1], entry[2], entry[4])].add(entry[3])
                more = self._served(entry) - served  # places too many serving a called key
                if more > 0:
                    servers = sorted(self.by_key[(entry[0], "in", entry[3] + entry[4])])
                    one, other, *_ = {server[2]: server for server in servers}.values()
                    callers = self.by_key[(entry[0], "out", entry[3] + entry[4])]
                    involved = (*servers, *callers)
                    found += [Conflict("served", one, other, involved=involved)] * more
        self.bad += len(found)
        return found

    def remove(self, link: Link, key: str) -> None:
        for entry in link.ends(key) or ():
            self.count[entry] -= 1
            if self.count[entry] == 0:
                del self.count[entry]
                served = self._served(entry)
                self.by_key[(entry[0], entry[1], entry[3] + entry[4])].discard(entry)
                self.by_name[(entry[0], entry[1], entry[2], entry[4])].discard(entry[3])
                self.bad -= len(self._meet(entry, leaving=True)) + served - self._served(entry)

    def _served(self, entry: Entry) -> int:
        """How many places too many serve the service key of ``entry``, if it is called."""
        key = entry[3] + entry[4]
        if entry[0].on_topic or not self.by_key[(entry[0], "out", key)]:
            return 0
        return max(0, len({server[2] for server in self.by_key[(entry[0], "in", key)]}) - 1)

    def _meet(self, entry: Entry, leaving: bool = False) -> list[Conflict]:
        """The wrongs ``entry`` makes with the others (it is not among them yet, or not any
        more); pairs of bridges are recorded as it comes and forgotten as it leaves."""
        kind, side, place, namespace, name = entry
        key, other = namespace + name, "in" if side == "out" else "out"
        found = []
        for peer in list(self.by_key[(kind, other, key)]):
            if (peer[2], peer[3]) == (place, namespace):
                continue  # one bridge: it never takes back its own data
            out, into = (entry, peer) if side == "out" else (peer, entry)
            delivery = (kind, out[2], out[4], into[2], into[4])
            pairs = self.pairs[delivery]
            if leaving:
                pairs.discard((out, into))
            if delivery not in self.wanted:
                found.append(Conflict("unconnected", out, into, involved=(out, into)))
            elif pairs:  # another pair of bridges delivers it already
                involved = (out, into, *(e for pair in pairs for e in pair))
                found.append(Conflict("twice", out, into, involved=involved))
            if not leaving:
                pairs.add((out, into))
        for spaced in self.by_name[(kind, other, place, name)] - {namespace}:
            peer = (kind, other, place, spaced, name)
            first, second = (entry, peer) if side == "in" else (peer, entry)
            found.append(Conflict("echo", first, second, involved=(first, second)))
        return found
