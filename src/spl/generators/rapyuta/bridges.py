"""The Rapyuta interfaces and connections that carry the crossing flows of a product.

:mod:`spl.resolver.architecture.wiring` finds every flow whose two nodes run in different places
(robot, or one partition of a cloud container); Rapyuta carries each with one bridge:
a Subscriber where the data is produced and a Publisher where it is consumed, or a
ServiceProvider next to the client and a ServiceClient next to the server. Bridges are
keyed by their two ends, so several nodes sharing a topic or a server share one
bridge. Interface tags are the TSM's canonical endpoint-interface names, each begun by
the endpoint prefix of its side's kind (``InterfaceKind.endpoint_prefix``):
``sub_<Topic>``, ``pub_<Topic>``, ``srv_<ServerNode>_<service>``,
``cli_<ServerNode>_<service>`` (where another bridge of the place has that tag, the next
name the TSM language gives, :func:`spl.resolver.architecture.endpoints.endpoint_name_choices`:
qualified with
the server's or topic's container); robots take ``...Converter`` types, containers
``...Interface`` types; connections run from the side the data or call enters
(``tagA``) to the side that delivers it (``tagB``).

A bridge is declared in the file of the robot it belongs to (its robot or private
partition is one side); a bridge between two shared partitions is made once, by the
file that declares them (:func:`spl.generators.rapyuta.configurations.declare_once`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Diagnostic
from spl.metamodels.interface_kinds import InterfaceKind, side
from spl.resolver.architecture.endpoints import endpoint_name_choices
from spl.resolver.architecture.flows import FlowTable, node_of
from spl.resolver.architecture.placement import Place, Placement
from spl.resolver.architecture.wiring import Crossing, Wiring

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

# one side of a bridge: the place, the interface tag, its engine entry, and the topic or
# node server it is for (which qualifies the tag when another interface has it)
End = tuple[Place, str, dict[str, str], "tsm_types.Topic | tsm_types.ServiceServer"]


@dataclass(frozen=True, order=True)
class Bridge:
    """One connection: data or calls enter at ``source`` and are delivered at ``target``."""

    source: Place
    source_tag: str
    target: Place
    target_tag: str

    def as_json(self) -> dict[str, str]:
        return {
            "tagA": f"{self.source.tag}/{self.source_tag}",
            "tagB": f"{self.target.tag}/{self.target_tag}",
        }


def _end(
    place: Place,
    tag: str,
    kind: InterfaceKind,
    cls: str | None,
    addr: str,
    target: tsm_types.Topic | tsm_types.ServiceServer,
) -> End:
    """One side of a bridge: the interface ``tag`` on ``place``, an interface of ``kind``
    to Rapyuta, and its engine entry."""
    suffix = "Converter" if place.is_robot else "Interface"
    spec = {
        "eTag": place.tag,
        "iTag": tag,
        "iType": f"{kind.rapyuta_role}{suffix}",
        "iCls": cls or "",
        "addr": addr,
    }
    return place, tag, spec, target


def _bridged_ends(crossing: Crossing) -> list[tuple[End, End]]:
    """The ends of every bridge carrying ``crossing``, where it enters and where it is
    delivered: one bridge, or one topic bridge per ROS 1 topic the interface is made of
    (an action's goal and cancel from the client's side, status, feedback and result
    back; ``Family.ros1_topics``, docs/deployment.md "Actions")."""
    parts = crossing.kind.ros1_topics
    if not parts:
        return [_ends(crossing)]
    server = crossing.target_element  # the node's server, as for a service
    node = node_of(cast("tsm_types.ServiceServer", server)).name
    bridged = []
    for part in parts:  # each bridged as what it is (Family.ros1_topics' carrier)
        carrier = part.carrier
        entering = side(carrier, not carrier.flows_from_provider)
        delivering = side(carrier, carrier.flows_from_provider)
        towards = part.from_consumer
        source, target = (crossing.source, crossing.target)[:: 1 if towards else -1]
        names = (crossing.source_name, crossing.target_name)[:: 1 if towards else -1]
        tag = f"{node}_{server.name}_{part.suffix}"
        cls = part.message_of(server.type)
        bridged.append(
            (
                _end(
                    source,
                    f"{entering.endpoint_prefix}_{tag}",
                    entering,
                    cls,
                    f"{names[0]}/{part.suffix}",
                    server,
                ),
                _end(
                    target,
                    f"{delivering.endpoint_prefix}_{tag}",
                    delivering,
                    cls,
                    f"{names[1]}/{part.suffix}",
                    server,
                ),
            )
        )
    return bridged


def _ends(crossing: Crossing) -> tuple[End, End]:
    """The two interfaces of the bridge carrying ``crossing``: each faces the node
    interface next to it, so the bridge takes the other side of the family where the
    flow starts (a Subscriber next to the publisher, a ServiceProvider next to the
    client) and the side the flow starts at where it ends."""
    family = crossing.kind
    entering = side(family, not family.flows_from_provider)
    delivering = side(family, family.flows_from_provider)
    if family.on_topic:
        source_topic = cast("tsm_types.Topic", crossing.source_element)
        target_topic = cast("tsm_types.Topic", crossing.target_element)
        return (
            _end(
                crossing.source,
                f"{entering.endpoint_prefix}_{source_topic.name}",
                entering,
                source_topic.type,
                crossing.source_name,
                source_topic,
            ),
            _end(
                crossing.target,
                f"{delivering.endpoint_prefix}_{target_topic.name}",
                delivering,
                target_topic.type,
                crossing.target_name,
                target_topic,
            ),
        )
    server = crossing.target_element  # a service crossing's: the node's server
    tag = f"{node_of(cast('tsm_types.ServiceServer', server)).name}_{server.name}"
    return (
        _end(
            crossing.source,
            f"{entering.endpoint_prefix}_{tag}",
            entering,
            server.type,
            crossing.source_name,
            server,
        ),
        _end(
            crossing.target,
            f"{delivering.endpoint_prefix}_{tag}",
            delivering,
            server.type,
            crossing.target_name,
            server,
        ),
    )


def _declared_by(robot_id: str, crossing: Crossing) -> bool:
    """Whether the file of robot ``robot_id`` declares the bridge of ``crossing``: one
    side is the robot or one of its private partitions, or both sides are shared."""

    def mine(place: Place) -> bool:
        return place.owner == robot_id and place.kind in ("robot", "private")

    a, b = crossing.source, crossing.target
    return mine(a) or mine(b) or (a.shared and b.shared)


class Bridges:
    """Every bridge of the system, by the robot whose file declares it, and the engine
    entries of their interfaces (by ``(place tag, interface tag)``)."""

    def __init__(self, flows: FlowTable, placement: Placement, errors: list[Diagnostic]) -> None:
        self.errors = errors
        self.interfaces: dict[tuple[str, str], dict[str, str]] = {}
        self.of_robot: dict[int, set[Bridge]] = {}
        wiring = Wiring(flows, placement, errors)
        for robot in placement.robots:
            robot_id = placement.robot_ids[id(robot)]
            bridges: set[Bridge] = set()
            for crossing in wiring.crossings(robot):
                if _declared_by(robot_id, crossing):
                    for source, target in _bridged_ends(crossing):
                        source_tag, target_tag = self._register(source), self._register(target)
                        bridges.add(Bridge(source[0], source_tag, target[0], target_tag))
            self.of_robot[id(robot)] = bridges

    def _register(self, end: End) -> str:
        """The tag of ``end`` on its place: its canonical one unless another interface
        of the place has it, then the next the TSM language offers."""
        place, tag, spec, target = end
        for choice in endpoint_name_choices(tag, target):
            entry = {**spec, "iTag": choice}
            if self.interfaces.setdefault((place.tag, choice), entry) == entry:
                return choice
        raise AssertionError("endpoint_name_choices never ends")
