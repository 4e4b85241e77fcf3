"""SPL019: two instances of the template that would get one Rapyuta tag.

Each robot and each partition of a cloud container is deployed under a tag (the
robot_id; ``Container_robotid``, ``Container_group``, ``Container_public``), and the
bundle names files after it, so two instances with one tag (or tags differing only in
case) make a product that has both fail to resolve: a robot whose robot_id is
``MappingCloud_mappers`` beside the protected partition of ``MappingCloud`` in group
``mappers``.

The instances are the template's: every robot, and each partition of a cloud container
a robot reaches that some node can be in, with the sharing modes the .tsm gives its
nodes, and those the feature model's defaults and the listed products' selections
(``products/*.yaml``) give the nodes a resolution element uses (in the container they are
in, or migrate to). A warning, as SPL017: a product may set another robot_id in its
``deployment`` or another sharing mode, and may not have both instances.
"""

from __future__ import annotations

from collections import defaultdict

from spl.core.diagnostics import Diagnostic, ModelError
from spl.metamodels import tsm
from spl.resolver.architecture.placement import MODES, Placement, sharing_mode
from spl.resolver.line_checks.listed_products import Listed
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.transformations import moves, sharing_targets

CLASHING_TAGS = "SPL019"


def clashing_instance_tags(line: ProductLine, listed: Listed) -> list[Diagnostic]:
    """A warning for each tag clash, where resolve reports it (at the later instance's
    container); ``listed`` are the listed products, for the sharing modes they choose."""
    placement = Placement(line.tsm, [])  # a robot_id or group that is no tag: SPL018, parser
    robots_only = len(placement.clashes)  # two robots with one robot_id: SPL017
    modes = _possible_modes(line, listed)
    for robot in placement.robots:
        for cloud in placement.scope(robot):
            for mode in MODES:
                if mode in modes[id(cloud)]:
                    placement.place(cloud, mode, robot)
    return [
        Diagnostic(
            clash.location,
            f"{clash.message}; a product that has both fails to resolve",
            "warning",
            CLASHING_TAGS,
        )
        for clash in dict.fromkeys(placement.clashes[robots_only:])
    ]


def _possible_modes(line: ProductLine, listed: Listed) -> dict[int, set[str]]:
    """The sharing modes a node can have in each container, by container id."""
    Node = tsm().Node
    chosen: dict[str, set[str]] = defaultdict(set)  # by feature, the listed products' modes
    for _, selection in listed:
        if not isinstance(selection, ModelError):  # one that does not read is SPL015's
            for feature, mode in selection.sharing.items():
                chosen[feature].add(mode)
    modes: dict[int, set[str]] = defaultdict(set)
    for container in line.tsm.containers:
        for node in container.nodes:
            modes[id(container)].add(sharing_mode(node))
    for element in line.rm.elements:
        moved = moves(element)
        for node, target in moved:
            modes[id(target)].add(sharing_mode(node))
        config = element.feature.sharing
        if config is None:
            continue
        feature_modes = {config.mode.name} | chosen[element.feature.name]
        for shared in sharing_targets(element):
            if isinstance(shared, Node):  # not a store
                modes[id(shared.eContainer())] |= feature_modes
        for _, target in moved:
            modes[id(target)] |= feature_modes
    return modes
