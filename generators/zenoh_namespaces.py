"""The bridge namespaces under which Zenoh carries exactly the flow table (docs/deployment.md,
"How the bridges' namespaces are chosen").

What a choice of keys does wrong is :mod:`spl.generators.zenoh_keys`'. A robot runs one
bridge: its namespace is one choice for all of its links. The other choices are the keys
of links between two cloud instances. The candidates are the namespaces ``n + p``, ``n``
none or a robot's own (``/<robotID>``), ``p`` none or a rename prefix (a link whose two
names differ by a prefix), for the robot's bridge or for either end of a link. The choice
the generator always made first (each robot under its own, a link between cloud
instances under the robot of its private end, or none) is tried first and kept where it
is exact, so products it carried keep their bytes; elsewhere a backtracking search takes
the first exact choice in order of preference, or says that none is.
"""

from __future__ import annotations

from collections import defaultdict

from spl.generators.zenoh_keys import Conflict, KeySpace, Link, Token, robot_namespace, token

# the most choices tried before the search gives up (docs/deployment.md says so)
TRIES = 50_000

Variable = str | int  # a robotID (its bridge's namespace) or a link's index (its key)


class Choice:
    """The robots' bridge namespaces and the keys of the links between cloud instances:
    the usual ones, and where they are not exact a search over the candidates, component
    by component (choices of different tokens never meet). :meth:`choose` leaves the
    exact choice in :attr:`namespaces` and :attr:`keys`, or returns the usual choice's
    conflicts where none is exact."""

    def __init__(self, links: list[Link], robots: list[str], limit: int = TRIES) -> None:
        self.links = links
        self.limit = limit
        self.robots = robots
        self.space = KeySpace({link.delivery for link in links})
        self.namespaces: dict[str, str] = {}
        self.keys: dict[int, str] = {}
        self.at: dict[str, list[int]] = defaultdict(list)  # robotID -> its links
        for index, link in enumerate(links):
            for robot in link.robots:
                self.at[robot].append(index)
        self.usual_keys: dict[int, str] = {}  # the usual choice, kept to name its conflicts
        self.tries = 0
        self._candidates: list[str] | None = None

    @property
    def gave_up(self) -> bool:
        return self.tries > self.limit

    def choose(self) -> list[Conflict]:
        conflicts = self._usual()
        if not conflicts:
            return []
        left: list[Conflict] = []
        for variables, theirs in self._components(conflicts):
            if not self._search(variables):
                left += theirs
        return left

    # -- the usual choice ---------------------------------------------------------------
    def wanted(self, robot: str) -> set[str]:
        """The prefixes the renames at the robot ask its bridge's namespace to end with."""
        found = set()
        for link in (self.links[i] for i in self.at[robot]):
            at_source = link.source.is_robot and link.source.owner == robot
            own = link.source_name if at_source else link.target_name
            longest = link.longest()
            if longest is not None and longest != own:
                found.add(longest[: len(longest) - len(own)])
        return found

    def usual_namespace(self, robot: str) -> str:
        """``/<robotID>``, or the longest prefix the renames at the robot ask for."""
        wanted = self.wanted(robot)
        return min(wanted, key=lambda p: (-len(p), p)) if wanted else robot_namespace(robot)

    def usual_key(self, index: int) -> str | None:
        """Under the namespace of the robot a private end belongs to, else the target's
        name (no namespace at the target); ``None`` while that robot has none."""
        link = self.links[index]
        source, target = link.source, link.target
        if source.is_robot or (not target.is_robot and source.kind == "private"):
            namespace = self.namespaces.get(source.owner)
            return None if namespace is None else namespace + link.source_name
        if target.is_robot or target.kind == "private":
            namespace = self.namespaces.get(target.owner)
            return None if namespace is None else namespace + link.target_name
        return link.target_name

    def _usual(self) -> list[Conflict]:
        for robot in self.robots:
            self.namespaces[robot] = self.usual_namespace(robot)
        found: list[Conflict] = []
        for index, link in enumerate(self.links):
            key = self.usual_key(index)
            if key is None or not self._fits(link, key):
                found.append(Conflict("apart", link=link))
                continue
            found += self.space.add(link, key)
            self.keys[index] = key
        self.usual_keys = dict(self.keys)
        return found

    def _fits(self, link: Link, key: str) -> bool:
        """Whether ``key`` gives both ends a namespace, a robot's end its bridge's."""
        ends = link.ends(key)
        return ends is not None and all(
            not place.is_robot or self.namespaces.get(place.owner) == end[3]
            for place, end in zip((link.source, link.target), ends, strict=True)
        )

    # -- the search -----------------------------------------------------------------------
    def _components(self, conflicts: list[Conflict]) -> list[tuple[list[Variable], list[Conflict]]]:
        """The choices (robots first, then links between cloud instances, in model order)
        sharing tokens with a conflict, in groups that share none with each other."""
        parent: dict[Token, Token] = {}

        def root(t: Token) -> Token:
            while parent.setdefault(t, t) != t:
                t = parent[t]
            return t

        variables: list[tuple[Variable, set[Token]]] = []
        for robot in self.robots:
            tokens = {t for i in self.at[robot] for t in self._tokens(i)}
            variables += [(robot, tokens)] if tokens else []
        variables += [(i, self._tokens(i)) for i, link in enumerate(self.links) if not link.robots]
        for _, tokens in variables:
            first, *others = sorted(tokens)
            for other in others:
                parent[root(other)] = root(first)
        groups: dict[Token, tuple[list[Variable], list[Conflict]]] = {}
        for conflict in conflicts:
            key = root(min(conflict.tokens()))
            groups.setdefault(key, ([], []))[1].append(conflict)
        for variable, tokens in variables:
            group = groups.get(root(min(tokens)))
            if group is not None:
                group[0].append(variable)
        return list(groups.values())

    def _tokens(self, index: int) -> set[Token]:
        link = self.links[index]
        return {token(link.kind, link.source_name), token(link.kind, link.target_name)}

    def _search(self, variables: list[Variable]) -> bool:
        """Backtracking over the choices of one component, each choice's values in order
        of preference, keeping only what adds no conflict to the others' (``base``)."""
        for variable in variables:  # forget the usual choice of the component
            indexes = self.at[variable] if isinstance(variable, str) else [variable]
            for index in indexes:
                key = self.keys.pop(index, None)
                if key is not None:
                    self.space.remove(self.links[index], key)
            if isinstance(variable, str):
                del self.namespaces[variable]
        base = self.space.bad
        if not variables:
            return False
        values = [iter(self._values(variables[0]))]
        applied: list[list[tuple[int, str]]] = []
        while not self.gave_up:
            value = next(values[-1], None)
            if value is None:
                values.pop()
                if not applied:
                    return False
                self._undo(variables[len(applied) - 1], applied.pop())
                continue
            variable = variables[len(applied)]
            added = self._apply(variable, value)
            if added is None:
                continue
            if self.space.bad != base:
                self._undo(variable, added)
                continue
            applied.append(added)
            if len(applied) == len(variables):
                return True
            values.append(iter(self._values(variables[len(applied)])))
        return False

    def _values(self, variable: Variable) -> list[str]:
        if isinstance(variable, str):
            return list(dict.fromkeys([self.usual_namespace(variable), *self.candidates()]))
        link = self.links[variable]
        keys = [self.usual_key(variable)]
        keys += [c + link.source_name for c in self.candidates()]
        keys += [c + link.target_name for c in self.candidates()]
        return [k for k in dict.fromkeys(keys) if k is not None and link.ends(k) is not None]

    def candidates(self) -> list[str]:
        """``n + p``: ``n`` none or a robot's own namespace, ``p`` none or a rename prefix."""
        if self._candidates is None:
            renames = set()
            for link in self.links:
                longest = link.longest()
                shortest = min(link.source_name, link.target_name, key=len)
                if longest is not None and longest != shortest:
                    renames.add(longest[: len(longest) - len(shortest)])
            bases = ["", *(robot_namespace(robot) for robot in self.robots)]
            self._candidates = list(
                dict.fromkeys(n + p for n in bases for p in ["", *sorted(renames)])
            )
        return self._candidates

    def _apply(self, variable: Variable, value: str) -> list[tuple[int, str]] | None:
        """The links a choice places (a robot's: those whose robots all have theirs now),
        or ``None`` when one cannot be placed so."""
        self.tries += 1
        if isinstance(variable, int):
            self.space.add(self.links[variable], value)
            self.keys[variable] = value
            return [(variable, value)]
        self.namespaces[variable] = value
        added: list[tuple[int, str]] = []
        for index in self.at[variable]:
            link = self.links[index]
            if any(robot not in self.namespaces for robot in link.robots):
                continue  # placed with the other robot's choice
            key = self.usual_key(index)
            if key is None or not self._fits(link, key):
                self._undo(variable, added)
                return None
            self.space.add(link, key)
            self.keys[index] = key
            added.append((index, key))
        return added

    def _undo(self, variable: Variable, added: list[tuple[int, str]]) -> None:
        for index, key in added:
            self.space.remove(self.links[index], key)
            del self.keys[index]
        if isinstance(variable, str):
            del self.namespaces[variable]
