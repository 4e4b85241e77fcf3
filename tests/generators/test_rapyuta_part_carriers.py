"""A Rapyuta bridge carries each ROS 1 part of an interface as what the registry says
the part is (``PartTopic.carrier``, docs/architecture.md "Interface kinds"): actionlib's
five topics as topic bridges, and a part that is a service (dynamic_reconfigure's
``set_parameters``) as a service bridge, calls entering next to the client, so that a
family with such a part is bridged without an edit of the bridges."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from spl.generators.rapyuta.bridges import _bridged_ends
from spl.metamodels.interface_kinds import SERVICE, PartTopic
from spl.resolver.architecture.placement import Placement
from spl.resolver.architecture.wiring import Wiring
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

NAVIGATION = Path(__file__).parents[2] / "product_lines" / "navigation"


def _action_crossing():
    """The mission's goals to the cloud planner, in the shipped navigation line."""
    line = load_product_line(NAVIGATION)
    product = resolve(line, selection_from_list("Navigation,Differential,StaticMap")).product
    errors: list = []
    placement = Placement(product.system, errors)
    wiring = Wiring(product.flows, placement, errors)
    (robot,) = placement.robots
    (crossing,) = [c for c in wiring.crossings(robot) if c.kind.ros1_topics]
    assert not errors
    return crossing


def _ends(pair) -> tuple[tuple[str, str, str, str, str], ...]:
    """Each end as (place, tag, Rapyuta type, class, ROS name)."""
    return tuple(
        (place.tag, tag, spec["iType"], spec["iCls"], spec["addr"]) for place, tag, spec, _ in pair
    )


def test_each_part_is_bridged_as_what_it_is() -> None:
    crossing = _action_crossing()
    part = PartTopic("set_parameters", True, "dynamic_reconfigure/Reconfigure", SERVICE)
    varied = replace(
        crossing, kind=replace(crossing.kind, ros1_topics=(*crossing.kind.ros1_topics, part))
    )
    topics = [_ends(pair) for pair in _bridged_ends(crossing)]
    *same, called = [_ends(pair) for pair in _bridged_ends(varied)]
    assert same == topics
    # the five topics: a Subscriber where a part is sent, a Publisher where it arrives
    assert {(a[2], b[2]) for a, b in topics} == {
        ("SubscriberConverter", "PublisherInterface"),
        ("SubscriberInterface", "PublisherConverter"),
    }
    tag = "Planner_move_base_set_parameters"
    source, target = crossing.source_name, crossing.target_name
    assert called == (
        (crossing.source.tag, f"srv_{tag}", "ServiceProviderConverter", part.message,
         f"{source}/set_parameters"),
        (crossing.target.tag, f"cli_{tag}", "ServiceClientInterface", part.message,
         f"{target}/set_parameters"),
    )  # fmt: skip
