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
  calls, an input fed from outside); an instance a delivered publisher or caller feeds
  that is itself active. Only deployed instances count, over every robot at once (a
  shared instance is fed by every robot using it).
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

from spl.resolver.flows import TOPIC, Flow, FlowTable, node_of

if TYPE_CHECKING:
    from spl.metamodels import tsm_types
    from spl.resolver.placement import Place, Placement

Vertex = tuple[int, str]  # the node's index in model order, the tag of its place


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

    def foreign(place: Place) -> bool:
        return place.is_robot and place.owner != robot_id

    for flow in flows:
        if id(flow.source_container) not in allowed or id(flow.target_container) not in allowed:
            continue
        source = placement.node_place(node_of(flow.source), robot, claim=False)
        target = placement.node_place(node_of(flow.target), robot, claim=False)
        withheld = (foreign(source) and target.kind == "private") or (
            foreign(target) and source.kind == "private"
        )
        yield Delivery(flow, source, target, withheld)


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


def _edges(delivery: Delivery, index: dict[int, int]) -> list[Edge]:
    flow = delivery.flow
    source = (index[id(node_of(flow.source))], delivery.source.tag)
    target = (index[id(node_of(flow.target))], delivery.target.tag)
    if flow.kind == TOPIC:
        return [Edge(source, target, source, flow, True)]
    return [Edge(source, target, source, flow, True), Edge(target, source, source, flow, False)]


class PrivateInstances:
    """The private instances each robot of one resolved system gets, and why."""

    def __init__(self, placement: Placement, flows: FlowTable) -> None:
        self.placement = placement
        nodes = [n for c in placement.system.containers for n in c.nodes]
        # vertices name nodes by their model order, so every walk is the same each run
        self.index = {id(node): i for i, node in enumerate(nodes)}
        self.nodes = nodes
        # nodes some flow feeds (a subscriber, or a server): not self-starting
        self.fed = {self.index[id(node_of(f.target))] for f in flows}
        self.robot_tags = {placement.robot_ids[id(r)] for r in placement.robots}
        self.edges: dict[int, list[Edge]] = {}  # id(robot) -> the edges of its view
        self.candidates: dict[int, set[Vertex]] = {}  # id(robot) -> its private instances
        for robot in placement.robots:
            self.edges[id(robot)] = [
                edge
                for delivery in placed_flows(placement, flows, robot)
                if not delivery.withheld
                for edge in _edges(delivery, self.index)
            ]
            self.candidates[id(robot)] = {
                (self.index[id(node)], place.tag)
                for cloud in placement.scope(robot)
                for node in cloud.nodes
                if (place := placement.node_place(node, robot, claim=False)).kind == "private"
            }
        self.private = set().union(*self.candidates.values())
        self.active: set[Vertex] = set()
        self.reasons = self._settle()

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
        for edges in self.edges.values():
            for edge in edges:
                ends = (edge.giver, edge.taker)
                if any(v in self.private and v not in deployed for v in ends):
                    continue
                present.update(ends)
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
        robot's own instances (a least fixpoint: a chain may end at a kept instance)."""
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
        own = {(self.index[id(node)], robot_id) for node in robot.nodes}
        reasons: dict[Vertex, Reason] = {}
        while True:
            reached = _reach(own, forward, feeds=False)
            for vertex, reason in _reach(own, backward, feeds=True).items():
                reached.setdefault(vertex, reason)
            new = {v: r for v, r in reached.items() if v in candidates and v not in reasons}
            if not new:
                return reasons
            reasons.update(new)
            own.update(new)

    def reason(self, node: tsm_types.Node, robot: tsm_types.Container) -> Reason | None:
        """Why ``robot`` gets its instance of private ``node``; None: it gets none."""
        tag = self.placement.node_place(node, robot, claim=False).tag
        return self.reasons[id(robot)].get((self.index[id(node)], tag))


def _reach(
    start: set[Vertex], edges: defaultdict[Vertex, list[Edge]], feeds: bool
) -> dict[Vertex, Reason]:
    """The vertices reached from ``start`` along ``edges`` (downstream from it, or
    upstream when ``feeds``), breadth first so that each gets a shortest chain, given in
    the direction data travels."""
    parent: dict[Vertex, Edge | None] = dict.fromkeys(sorted(start))
    frontier = deque(parent)
    while frontier:
        for edge in edges[frontier.popleft()]:
            onward = edge.giver if feeds else edge.taker
            if onward not in parent:
                parent[onward] = edge
                frontier.append(onward)
    found: dict[Vertex, Reason] = {}
    for vertex, last in parent.items():
        chain: list[Edge] = []
        step = last
        while step is not None:
            chain.append(step)
            step = parent[step.taker if feeds else step.giver]
        if chain:
            found[vertex] = Reason(feeds, tuple(chain if feeds else reversed(chain)))
    return found
