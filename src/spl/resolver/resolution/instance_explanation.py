"""What ``spl explain`` says about cloud instances: where a cloud node runs and, for a
private node, why each robot gets its instance or none (docs/deployment.md, "Private
instances"); and what one instance, named by its tag, holds or why it is not deployed.

Every answer is read from the placement's own decision
(:class:`spl.resolver.architecture.private_instances.PrivateInstances`), the one every deployment
target follows, so the explanation cannot disagree with a bundle.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

from spl.resolver.architecture.flows import node_of
from spl.resolver.architecture.placement import MODES, Placement, sharing_mode
from spl.resolver.architecture.private_instances import Edge, Reason, placed_flows

if TYPE_CHECKING:
    from spl.metamodels import tsm_types
    from spl.resolver.architecture.product import ResolvedProduct

INSTANCES = {
    "private": "one per robot that feeds it or that it feeds",
    "protected": "one per group",
    "public": "one for all",
}


def placement_of(product: ResolvedProduct) -> Placement:
    return Placement(product.system, [], flows=product.flows)


def robot_ids(product: ResolvedProduct) -> list[str]:
    """The robotIDs of the product's robots, in model order (what ``--robot`` takes)."""
    placement = placement_of(product)
    return [placement.robot_ids[id(robot)] for robot in placement.robots]


def node_instances(
    node: tsm_types.Node, product: ResolvedProduct, robot_id: str | None = None
) -> list[str]:
    """Where a cloud node runs once deployed; for a private node, each robot using its
    container (or robot ``robot_id`` alone) with the reason it gets an instance or not."""
    placement = placement_of(product)
    mode = sharing_mode(node)
    if mode != "private":
        instances = [i for i in placement.cloud_instances() if node in i.nodes]
        return [f"deployed {mode}: {INSTANCES[mode]}"] + [
            f"instance {i.place.tag} for robot {', '.join(i.robots)}" for i in instances
        ]
    robots = [
        robot
        for robot in placement.robots
        if node.eContainer() in placement.scope(robot)
        and robot_id in (None, placement.robot_ids[id(robot)])
    ]
    if not robots:
        return []
    return [f"deployed private: {INSTANCES[mode]}"] + [
        private_instance(placement, node, robot) for robot in robots
    ]


def private_instance(placement: Placement, node: tsm_types.Node, robot: tsm_types.Container) -> str:
    """One line: robot's instance of private ``node`` and the chain that keeps it, or
    why the robot gets none."""
    robot_id = placement.robot_ids[id(robot)]
    tag = placement.node_place(node, robot, claim=False).tag
    reason = placement.private.reason(node, robot)
    if reason is not None:
        how = f"it feeds {robot_id}" if reason.feeds else f"{robot_id} feeds it"
        return f"instance {tag} for robot {robot_id}: {how}: {chain(placement, reason)}"
    return f"no instance for robot {robot_id} (not run in {tag}): {_absent(placement, node, robot)}"


def chain(placement: Placement, reason: Reason) -> str:
    """The chain of a reason in words, each end as ``<place tag>.<node>.<interface>``."""
    return "; ".join(_step(placement, edge) for edge in reason.chain)


def _step(placement: Placement, edge: Edge) -> str:
    flow = edge.flow
    giver, taker = _end(edge.giver[1], flow.source), _end(edge.taker[1], flow.target)
    if flow.kind.on_topic:  # data one way; a call goes, and its answer comes back
        return f"{giver} -> {taker}"
    if edge.trigger:
        return f"{giver} calls {taker}"
    # an answer: the giver is the server's place, the taker the client's
    return f"{_end(edge.giver[1], flow.target)} answers {_end(edge.taker[1], flow.source)}"


def _end(tag: str, interface: tsm_types.Interface) -> str:
    return f"{tag}.{node_of(interface).name}.{interface.name}"


def _absent(placement: Placement, node: tsm_types.Node, robot: tsm_types.Container) -> str:
    """Why ``robot`` gets no instance of private ``node``: what its instance would be
    fed by, and that no chain joins it with the robot's nodes."""
    robot_id = placement.robot_ids[id(robot)]
    decision = placement.private
    vertex = (decision.index[id(node)], placement.node_place(node, robot, claim=False).tag)
    others = [
        _end(d.source.tag, d.flow.source)
        for d in placed_flows(placement, placement.flows, robot)
        if d.withheld and node_of(d.flow.target) is node and d.source.is_robot
    ]
    idle = [
        _end(e.giver[1], e.flow.source)
        for e in decision.edges[id(robot)]
        if e.trigger and e.taker == vertex and e.giver not in decision.active
    ]
    if vertex[0] not in decision.fed or any(
        e.trigger and e.taker == vertex and e.giver in decision.active
        for e in decision.edges[id(robot)]
    ):
        return (
            f"no flow chain joins it with {robot_id}'s nodes: nothing of {robot_id} reaches "
            f"it and nothing it sends reaches {robot_id}"
        )
    why = []
    if others:
        why.append(
            f"{', '.join(dict.fromkeys(others))} of another robot, whose data a private "
            "instance never takes"
        )
    if idle:
        why.append(f"{', '.join(dict.fromkeys(idle))}, which nothing feeds there")
    fed = f" (fed only by {'; '.join(why)})" if why else ""
    return f"nothing feeds it in {robot_id}'s deployment{fed}, so it has nothing to send either"


class Candidate(NamedTuple):
    """A cloud instance some robot would use: its tag, sharing mode, TSM container, the
    robots using the container and the container's nodes of that mode."""

    tag: str
    mode: str
    container: tsm_types.CloudContainer
    robots: tuple[tsm_types.Container, ...]
    nodes: tuple[tsm_types.Node, ...]


def candidates(placement: Placement) -> dict[str, Candidate]:
    """Every instance tag the placement rule can give, deployed or not, by tag."""
    found: dict[str, Candidate] = {}
    for robot in placement.robots:
        for cloud in placement.scope(robot):
            for mode in MODES:
                nodes = tuple(n for n in cloud.nodes if sharing_mode(n) == mode)
                if nodes:
                    tag = placement.place(cloud, mode, robot, claim=False).tag
                    known = found.setdefault(tag, Candidate(tag, mode, cloud, (), nodes))
                    found[tag] = known._replace(robots=(*known.robots, robot))
    return found


def instance_explanation(product: ResolvedProduct, tag: str) -> list[str] | None:
    """The lines explaining the instance named ``tag``: what it runs and for whom, or,
    for a private instance its robot does not get, why each node is absent; None when no
    robot could have an instance of that tag."""
    placement = placement_of(product)
    candidate = candidates(placement).get(tag)
    if candidate is None:
        return None
    deployed = {i.place.tag: i for i in placement.cloud_instances()}.get(tag)
    what = f"{candidate.mode} instance of cloud container {candidate.container.name}"
    if candidate.mode != "private":
        robots = ", ".join(placement.robot_ids[id(r)] for r in candidate.robots)
        nodes = ", ".join(n.name for n in candidate.nodes)
        return [f"{tag}: {what} for robots {robots}: runs {nodes}"]
    robot = candidate.robots[0]
    robot_id = placement.robot_ids[id(robot)]
    if deployed is None:
        head = f"{tag}: not deployed: robot {robot_id} gets none of its private nodes"
    else:
        head = (
            f"{tag}: {what} for robot {robot_id}: runs {', '.join(n.name for n in deployed.nodes)}"
        )
    return [head] + [
        f"  {node.name}: {private_instance(placement, node, robot)}" for node in candidate.nodes
    ]
