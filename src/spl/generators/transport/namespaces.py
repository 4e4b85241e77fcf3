"""The bridge namespaces under which Zenoh carries exactly the flow table (docs/deployment.md,
"How the bridges' namespaces are chosen").

What a choice of keys does wrong is :mod:`spl.generators.transport.keys`'. A robot runs one
bridge: its namespace is one choice for all of its links; the other choices are the keys
of links between cloud instances. The candidates are ``n + p``, ``n`` none or a robot's
own namespace, ``p`` none or a rename prefix, for a robot's bridge or either end of a
link. The usual choice (each robot under its own, a link between cloud instances under
the robot of its private end, or none) is kept where exact, so products it carried keep
their bytes; elsewhere the search (Prosser's conflict-directed backjumping: a choice with
no value left goes back to the last choice its conflicts involve, past those that play
no part) takes the first exact choice in order of preference, or says that none is.
"""

from __future__ import annotations

from collections import Counter, defaultdict

from spl.generators.transport.keys import (
    NAMESPACE,
    Conflict,
    Entry,
    KeySpace,
    Link,
    Token,
    robot_namespace,
    token,
)

# the most choices tried before the search gives up (docs/deployment.md says so)
TRIES = 50_000

Variable = str | int  # a robotID (its bridge's namespace) or a link's index (its key)


class Choice:
    """The robots' bridge namespaces and the links' keys, searched per component (choices
    of different tokens never meet): :meth:`choose` leaves the exact choice in
    :attr:`namespaces` and :attr:`keys`, or returns the usual one's conflicts."""

    def __init__(self, links: list[Link], robots: list[str], limit: int = TRIES) -> None:
        self.links = links
        self.limit = limit
        self.robots = robots
        self.space = KeySpace({link.delivery for link in links})
        self.namespaces: dict[str, str] = {}
        self.keys: dict[int, str] = {}
        self.at: dict[str, list[int]] = defaultdict(list)  # robotID -> its links
        self.near: dict[str, dict[str, None]] = defaultdict(dict)  # place -> robots there
        for index, link in enumerate(links):
            for robot in link.robots:
                self.at[robot].append(index)
                for place in (link.source.tag, link.target.tag):
                    self.near[place][robot] = None
        self.placed: dict[Entry, set[int]] = defaultdict(set)  # the links behind each entry
        self.usual_keys: dict[int, str] = {}  # the usual choice, kept to name its conflicts
        self.tries = 0
        self._candidates: list[str] | None = None
        names = {n for link in links for n in (link.source_name, link.target_name)}
        names |= self._renames()
        # robots' own namespaces no ROS name or rename prefix begins with (:meth:`_fresh`)
        self.swappable = {
            label
            for label in map(robot_namespace, robots)
            if NAMESPACE.fullmatch(label)
            and not any(n == label or n.startswith(label + "/") for n in names)
        }
        self._labels: dict[str, str | None] = {}  # first segment -> swappable namespace
        self.in_use: Counter[str | None] = Counter()  # swappable namespaces in the choice

    @property
    def gave_up(self) -> bool:
        return self.tries > self.limit

    def choose(self) -> list[Conflict]:
        conflicts = self._usual()
        if not conflicts:
            return []
        left: list[Conflict] = []
        for variables, theirs in self._components(conflicts):
            if not self._search(self._order(variables, theirs)):
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
            self._name(robot, self.usual_namespace(robot))
        found: list[Conflict] = []
        for index, link in enumerate(self.links):
            key = self.usual_key(index)
            if key is None or not self._fits(link, key):
                found.append(Conflict("apart", link=link))
                continue
            found += self._place(index, key)
        self.usual_keys = dict(self.keys)
        return found

    def _fits(self, link: Link, key: str) -> bool:
        """Whether ``key`` gives both ends a namespace, a robot's end its bridge's."""
        ends = link.ends(key)
        return ends is not None and all(
            not place.is_robot or self.namespaces.get(place.owner) == end[3]
            for place, end in zip((link.source, link.target), ends, strict=True)
        )

    def _place(self, index: int, key: str) -> list[Conflict]:
        link = self.links[index]
        for entry in link.ends(key) or ():
            self.placed[entry].add(index)
        self.keys[index] = key
        self.in_use[self._label(key)] += 1
        return self.space.add(link, key)

    def _unplace(self, index: int) -> None:
        key = self.keys.pop(index)
        link = self.links[index]
        self.space.remove(link, key)
        self.in_use[self._label(key)] -= 1
        for entry in link.ends(key) or ():
            self.placed[entry].discard(index)

    def _name(self, robot: str, namespace: str) -> None:
        self.namespaces[robot] = namespace
        self.in_use[self._label(namespace)] += 1

    def _unname(self, robot: str) -> None:
        self.in_use[self._label(self.namespaces.pop(robot))] -= 1

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
        # in model order (the choices of one group count the namespaces the others use)
        rank = {variable: k for k, (variable, _) in enumerate(variables)}
        return sorted(groups.values(), key=lambda g: rank[g[0][0]] if g[0] else len(rank))

    def _tokens(self, index: int) -> set[Token]:
        link = self.links[index]
        return {token(link.kind, link.source_name), token(link.kind, link.target_name)}

    def _order(self, variables: list[Variable], conflicts: list[Conflict]) -> list[Variable]:
        """The robots, then the links between cloud instances, each behind the conflicts
        first, then sharing places with them, and so on (in a fleet, the robots far from a
        conflict come last and play no part in refuting a choice near it), the rest in
        model order."""
        links: dict[Variable, list[int]] = {
            v: self.at[v] if isinstance(v, str) else [v] for v in variables
        }
        near: dict[str, dict[Variable, None]] = defaultdict(dict)
        for variable in variables:
            for index in links[variable]:
                for place in (self.links[index].source.tag, self.links[index].target.tag):
                    near[place][variable] = None
        start = [
            owner
            for conflict in conflicts
            for index in (
                [self.links.index(conflict.link)]
                if conflict.link is not None
                else [i for entry in conflict.involved for i in self.placed[entry]]
            )
            for owner in self._owners(index)
        ]
        rank = {v: k for k, v in enumerate(variables)}  # model order, whatever the hashes
        order = sorted({v for v in start if v in links}, key=rank.__getitem__)
        seen, walked = set(order), set()
        for variable in order:  # grows while it is read: a breadth-first walk
            for index in links[variable]:
                for place in (self.links[index].source.tag, self.links[index].target.tag):
                    if place not in walked:
                        walked.add(place)
                        order += [v for v in near[place] if v not in seen]
                        seen.update(near[place])
        order += [v for v in variables if v not in seen]
        # robots first: a link's usual key and its neighbours' keys follow their choices
        return sorted(order, key=lambda v: not isinstance(v, str))

    def _search(self, variables: list[Variable]) -> bool:
        """Conflict-directed backjumping over the choices of one component, each choice's
        values in order of preference, keeping only what adds no conflict."""
        for variable in variables:  # forget the usual choice of the component
            for index in self.at[variable] if isinstance(variable, str) else [variable]:
                if index in self.keys:
                    self._unplace(index)
            if isinstance(variable, str):
                self._unname(variable)
        if not variables:
            return False
        position = {variable: k for k, variable in enumerate(variables)}
        values = [iter(self._values(variables[0]))]
        blamed: list[set[int]] = [set()]  # per choice: the earlier ones its failures involve
        applied: list[list[int]] = []
        while not self.gave_up:
            k = len(applied)
            value = next(values[k], None)
            if value is None:  # no value left: back to the last choice to blame
                culprits = blamed.pop()
                values.pop()
                if not culprits:
                    for j in reversed(range(k)):
                        self._undo(variables[j], applied.pop())
                    return False
                back = max(culprits)
                while len(applied) > back:
                    self._undo(variables[len(applied) - 1], applied.pop())
                    if len(applied) > back:
                        values.pop()
                        blamed.pop()
                blamed[back] |= culprits - {back}
                continue
            added, culprits = self._apply(variables[k], value, position)
            if added is None:
                blamed[k] |= {c for c in culprits if c < k}
                continue
            applied.append(added)
            if len(applied) == len(variables):
                return True
            values.append(iter(self._values(variables[len(applied)])))
            blamed.append(set())
        return False

    def _values(self, variable: Variable) -> list[str]:
        """A robot's usual namespace then the candidates; a link's usual key, then the
        keys under the namespaces of the robots with links at its ends, then under one
        nothing uses yet, then the others; of the robots' own namespaces nothing uses
        yet, one only (:meth:`_fresh`)."""
        if isinstance(variable, str):
            values = list(dict.fromkeys([self.usual_namespace(variable), *self.candidates()]))
            return self._fresh(values, robot_namespace(variable))[0]
        link = self.links[variable]
        names = (link.source_name, link.target_name)
        usual = self.usual_key(variable)
        first = [usual] if usual is not None else []
        first += [
            self.namespaces[robot] + name
            for place in (link.source.tag, link.target.tag)
            for robot in self.near[place]
            if robot in self.namespaces
            for name in names
        ]
        keys = [*first, *(n + name for n in self.candidates() for name in names)]
        kept, fresh = self._fresh([k for k in dict.fromkeys(keys) if link.ends(k)], None)
        rank = {k: 0 if k in first else 1 if self._label(k) == fresh else 2 for k in kept}
        return sorted(kept, key=rank.__getitem__)

    def _fresh(self, values: list[str], own: str | None) -> tuple[list[str], str | None]:
        """``values`` but those under a robot's own namespace that nothing uses yet, one
        kept (``own`` if it is one, else the first), and that one: such namespaces can be
        swapped throughout a choice without changing what it delivers (no ROS name or
        rename prefix begins with them), so one stands for all."""
        labels = [self._label(v) for v in values]
        free = [label for label in labels if label is not None and not self.in_use[label]]
        keep = own if own in free else next(iter(free), None)
        kept = [
            v
            for v, label in zip(values, labels, strict=True)
            if label is None or self.in_use[label] or label == keep
        ]
        return kept, keep

    def _label(self, text: str) -> str | None:
        """The robot's own namespace ``text`` begins with, if one that can be swapped."""
        head = "/" + text.split("/")[1] if text.startswith("/") else ""
        if head not in self._labels:
            self._labels[head] = head if head in self.swappable else None
        return self._labels[head]

    def candidates(self) -> list[str]:
        """``n + p``: ``n`` none or a robot's own namespace, ``p`` none or a rename prefix."""
        if self._candidates is None:
            bases = ["", *(robot_namespace(robot) for robot in self.robots)]
            renames = ["", *sorted(self._renames())]
            self._candidates = list(dict.fromkeys(n + p for n in bases for p in renames))
        return self._candidates

    def _renames(self) -> set[str]:
        """The prefixes by which the links' two names differ."""
        found = set()
        for link in self.links:
            longest = link.longest()
            shortest = min(link.source_name, link.target_name, key=len)
            if longest is not None and longest != shortest:
                found.add(longest[: len(longest) - len(shortest)])
        return found

    def _apply(
        self, variable: Variable, value: str, position: dict[Variable, int]
    ) -> tuple[list[int] | None, set[int]]:
        """The links a choice places (a robot's: those whose robots all have theirs now),
        or ``None`` and the positions of the choices to blame when it adds a conflict."""
        self.tries += 1
        if isinstance(variable, int):
            return self._placed([variable], self._place(variable, value), variable, position)
        self._name(variable, value)
        added: list[int] = []
        conflicts: list[Conflict] = []
        for index in self.at[variable]:
            link = self.links[index]
            if any(robot not in self.namespaces for robot in link.robots):
                continue  # placed with the other robot's choice
            key = self.usual_key(index)
            if key is None or not self._fits(link, key):
                self._undo(variable, added)
                others = {position.get(r, -1) for r in link.robots if r != variable}
                return None, others - {-1}
            conflicts += self._place(index, key)
            added.append(index)
        return self._placed(added, conflicts, variable, position)

    def _placed(
        self,
        added: list[int],
        conflicts: list[Conflict],
        variable: Variable,
        position: dict[Variable, int],
    ) -> tuple[list[int] | None, set[int]]:
        """``added`` when no conflict came of it, else nothing and the choices to blame."""
        if not conflicts:
            return added, set()
        # one conflict refuses the value: blame the one whose choices came first, so that
        # the search goes back as far as it can
        blames = [
            {
                position.get(owner, -1)
                for entry in conflict.involved
                for index in self.placed[entry]
                for owner in self._owners(index)
                if owner != variable
            }
            - {-1}
            for conflict in conflicts
        ]
        self._undo(variable, added)
        return None, min(blames, key=lambda blame: (max(blame, default=-1), sorted(blame)))

    def _owners(self, index: int) -> list[Variable]:
        """The choices a link's key follows from: its robots', or its own."""
        robots: list[Variable] = [*self.links[index].robots]
        return robots or [index]

    def _undo(self, variable: Variable, added: list[int]) -> None:
        for index in added:
            self._unplace(index)
        if isinstance(variable, str):
            self._unname(variable)
