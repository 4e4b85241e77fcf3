"""Which private instances each robot gets (docs/deployment.md, "Private instances").

A private cloud node runs once per robot, but only for a robot that can feed it or be
fed by it: an instance that nothing of its robot ever reaches, and whose output never
reaches its robot, would be a pod, an image and a bridge receiving nothing. The rule,
on the flow table placed for each robot (``placed_flows``):

- An *edge* is one delivery of a robot's deployment between two node instances: a
  publisher to a subscriber, a client's calls to a server, and the server's answers
  back to the client.
- An instance is *active* when data reaches it or it makes its own: every robot node;
  a cloud node no flow of the table feeds (a timer-driven publisher, a node that only
  calls, an input fed from outside or left unfed); an instance a delivered publisher
  or caller feeds that is itself active. Only deployed instances count, over every
  robot at once (a shared instance is fed by every robot using it).
- An edge *carries data* when its sender is active: the publisher, the caller, and for
  answers the caller again (a server answers only the calls it gets).
- Robot R's *own* instances are its robot nodes and the private instances it keeps. R
  keeps a private instance when a chain of edges that carry data leads from its own
  instances to it (R feeds it) or from it to them (it feeds R), through shared
  instances and R's other private instances; never through another robot, whose data
  R's private instances never take (docs/semantics.md F4).

Keeping is a least fixpoint per robot (an instance chained only to another of R's kept
instances is kept too); activity counts the instances kept, so the two are settled
together, from every candidate instance down, until neither changes.
"""

from __future__ import annotations

from collections import defaultdict, deque
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from spl.resolver.architecture.flows import Flow, FlowTable, node_of

if TYPE_CHECKING:
    from spl.metamodels import tsm_types
    from spl.resolver.architecture.placement import Place, Placement

Vertex = tuple[int, str]  # the node's index in model order, the tag of its place
# a flow table row: the flow, its source and target nodes, their containers' ids
Row = tuple[Flow, "tsm_types.Node", "tsm_types.Node", int, int]


@dataclass(frozen=True)
class Delivery:
    """A flow as one robot's deployment places it."""

    flow: Flow
    source: Place
    target: Place
    # not delivered in this view: a private partition and another robot, or a private
    # instance the robot does not get
    withheld: bool


def placed_flows(
    placement: Placement, flows: FlowTable, robot: tsm_types.Container
) -> Iterator[Delivery]:
    """Every flow between two containers of ``robot``'s view, placed, in table order;
    ``withheld`` when a private partition would serve another robot (what robot gets
    is not yet asked here)."""
    robot_id = placement.robot_ids[id(robot)]
    allowed = {id(c) for c in placement.view(robot)}
    places: dict[int, Place] = {}  # id(node) -> its place, each node placed once

    def place_of(node: tsm_types.Node) -> Place:
        found = places.get(id(node))
        if found is None:
            found = places[id(node)] = placement.node_place(node, robot, claim=False)
        return found

    for flow in flows:
        if id(flow.source_container) not in allowed or id(flow.target_container) not in allowed:
            continue
        source, target = place_of(node_of(flow.source)), place_of(node_of(flow.target))
        yield Delivery(flow, source, target, serves_another(source, target, robot_id))


def serves_another(source: Place, target: Place, robot_id: str) -> bool:
    """Whether a flow between two places would have a private partition serve a robot
    other than ``robot_id``, whose view this is: withheld (docs/semantics.md F4)."""
    return (source.is_robot and source.owner != robot_id and target.kind == "private") or (
        target.is_robot and target.owner != robot_id and source.kind == "private"
    )


@dataclass(frozen=True)
class Edge:
    """Data going from ``giver`` to ``taker`` along ``flow``; ``caller`` is the vertex
    whose activity makes it carry data (the publisher or client)."""

    giver: Vertex
    taker: Vertex
    caller: Vertex
    flow: Flow
    trigger: bool  # a publication or a call (it makes the taker active); not an answer


@dataclass(frozen=True)
class Reason:
    """Why a robot keeps a private instance: the edges of one chain joining it with the
    robot's own instances, in the direction the data travels."""

    feeds: bool  # True: the instance's data reaches the robot; False: the robot's reaches it
    chain: tuple[Edge, ...]


class PrivateInstances:
    """The private instances each robot of one resolved system gets, and why."""

    def __init__(self, placement: Placement, flows: FlowTable) -> None:
        self.placement = placement
        nodes = [n for c in placement.system.containers for n in c.nodes]
        # vertices name nodes by their model order, so every walk is the same each run
        self.index = {id(node): i for i, node in enumerate(nodes)}
        # each row once: (flow, source node, target node, their containers' ids)
        rows = [
            (
                f,
                node_of(f.source),
                node_of(f.target),
                id(f.source_container),
                id(f.target_container),
            )
            for f in flows
        ]
        # nodes some flow feeds (a subscriber, or a server): not self-starting
        self.fed = {self.index[id(target)] for _, _, target, _, _ in rows}
        self.robot_tags = {placement.robot_ids[id(r)] for r in placement.robots}
        self.candidates: dict[int, set[Vertex]] = {}  # id(robot) -> its private instances
        for robot in placement.robots:
            self.candidates[id(robot)] = {
                (self.index[id(node)], place.tag)
                for cloud in placement.scope(robot)
                for node in cloud.nodes
                if (place := placement.node_place(node, robot, claim=False)).kind == "private"
            }
        self.private = set().union(*self.candidates.values())
        self.edges: dict[int, list[Edge]] = {}  # id(robot) -> the edges of its view
        for robot in placement.robots if self.private else ():  # none: nothing to decide
            self.edges[id(robot)] = self._view(robot, rows)
        self.active: set[Vertex] = set()
        # id(robot) -> node index -> why the robot keeps its instance of that node
        self.reasons: dict[int, dict[int, Reason]] = {
            robot: {vertex[0]: reason for vertex, reason in found.items()}
            for robot, found in (self._settle() if self.private else {}).items()
        }

    def _view(self, robot: tsm_types.Container, rows: list[Row]) -> list[Edge]:
        """The edges of ``robot``'s view, in table order: the rows :func:`placed_flows`
        delivers (not withheld), a service row both ways."""
        placement = self.placement
        robot_id = placement.robot_ids[id(robot)]
        allowed = {id(c) for c in placement.view(robot)}
        places: dict[int, Place] = {}
        edges = []
        for flow, source_node, target_node, source_container, target_container in rows:
            if source_container not in allowed or target_container not in allowed:
                continue
            ends = []
            for node in (source_node, target_node):
                place = places.get(id(node))
                if place is None:
                    place = places[id(node)] = placement.node_place(node, robot, claim=False)
                ends.append(place)
            source, target = ends
            if serves_another(source, target, robot_id):
                continue  # withheld: a private partition serves its own robot alone
            giver = (self.index[id(source_node)], source.tag)
            taker = (self.index[id(target_node)], target.tag)
            edges.append(Edge(giver, taker, giver, flow, True))
            if not flow.kind.on_topic:  # a call: the server's answers back to the client
                edges.append(Edge(taker, giver, giver, flow, False))
        return edges

    def _settle(self) -> dict[int, dict[Vertex, Reason]]:
        """Activity and keeping, from every candidate deployed down to a fixpoint (each
        round keeps a subset of the last: fewer instances, fewer active ones)."""
        deployed = set(self.private)
        while True:
            active = self._active(deployed)
            reasons = {id(r): self._kept(r, active) for r in self.placement.robots}
            kept = {v for found in reasons.values() for v in found}
            if kept == deployed:
                self.active = active  # the instances data reaches, as deployed
                return reasons
            deployed = kept

    def _active(self, deployed: set[Vertex]) -> set[Vertex]:
        """The deployed instances data reaches or that make their own, over every robot's
        view at once."""
        triggers: defaultdict[Vertex, list[Vertex]] = defaultdict(list)
        present = set(deployed)
        absent = self.private - deployed
        for edges in self.edges.values():
            for edge in edges:
                if edge.giver in absent or edge.taker in absent:
                    continue
                present.add(edge.giver)
                present.add(edge.taker)
                if edge.trigger:
                    triggers[edge.giver].append(edge.taker)
        active = {v for v in present if v[1] in self.robot_tags or v[0] not in self.fed}
        frontier = deque(sorted(active))
        while frontier:
            for taker in triggers[frontier.popleft()]:
                if taker not in active:
                    active.add(taker)
                    frontier.append(taker)
        return active

    def _kept(self, robot: tsm_types.Container, active: set[Vertex]) -> dict[Vertex, Reason]:
        """The private instances ``robot`` keeps, each with a chain joining it with the
        robot's own instances (a least fixpoint: a chain may end at a kept instance, so
        each round walks on from the instances the last one kept)."""
        robot_id = self.placement.robot_ids[id(robot)]
        others = self.robot_tags - {robot_id}
        candidates = self.candidates[id(robot)]
        forward: defaultdict[Vertex, list[Edge]] = defaultdict(list)
        backward: defaultdict[Vertex, list[Edge]] = defaultdict(list)
        for edge in self.edges[id(robot)]:
            if edge.giver[1] in others or edge.taker[1] in others:
                continue  # another robot's: R's private instances never take its data
            if edge.caller in active:
                forward[edge.giver].append(edge)
                backward[edge.taker].append(edge)
        start = sorted((self.index[id(node)], robot_id) for node in robot.nodes)
        downstream: dict[Vertex, Edge | None] = {}  # vertex -> the edge it was reached by
        upstream: dict[Vertex, Edge | None] = {}
        reasons: dict[Vertex, Reason] = {}
        while start:
            found = _reach(start, forward, downstream, feeds=False, wanted=candidates)
            for vertex, reason in _reach(
                start, backward, upstream, feeds=True, wanted=candidates
            ).items():
                found.setdefault(vertex, reason)
            new = {v: r for v, r in found.items() if v not in reasons}
            reasons.update(new)
            start = sorted(new)
        return reasons

    def reason(self, node: tsm_types.Node, robot: tsm_types.Container) -> Reason | None:
        """Why ``robot`` gets its instance of private ``node``; None: it gets none."""
        return self.reasons.get(id(robot), {}).get(self.index[id(node)])


def _reach(
    start: list[Vertex],
    edges: defaultdict[Vertex, list[Edge]],
    parent: dict[Vertex, Edge | None],
    feeds: bool,
    wanted: set[Vertex],
) -> dict[Vertex, Reason]:
    """The vertices of ``wanted`` first reached from ``start`` along ``edges``
    (downstream from it, or upstream when ``feeds``), breadth first so that each gets a
    shortest chain, given in the direction data travels. ``parent`` holds the vertices
    reached before, which are not walked again."""
    frontier = deque(v for v in start if v not in parent)
    parent.update(dict.fromkeys(frontier))
    reached = []
    while frontier:
        for edge in edges[frontier.popleft()]:
            onward = edge.giver if feeds else edge.taker
            if onward not in parent:
                parent[onward] = edge
                frontier.append(onward)
                reached.append(onward)
    found: dict[Vertex, Reason] = {}
    for vertex in reached:
        if vertex not in wanted:
            continue
        chain: list[Edge] = []
        step = parent[vertex]
        while step is not None:
            chain.append(step)
            step = parent[step.taker if feeds else step.giver]
        found[vertex] = Reason(feeds, tuple(chain if feeds else reversed(chain)))
    return found
