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
from typing import Any

from spl.diagnostics import Diagnostic, ModelError
from spl.metamodels import tsm
from spl.resolver.placement import MODES, Placement, sharing_mode
from spl.resolver.product_line import ProductLine
from spl.resolver.product_selection import load_selection_file

CLASHING_TAGS = "SPL019"


def clashing_instance_tags(line: ProductLine) -> list[Diagnostic]:
    """A warning for each tag clash, where resolve reports it (at the later instance's
    container)."""
    placement = Placement(line.tsm, [])  # a robot_id or group that is no tag: SPL018, parser
    robots_only = len(placement.clashes)  # two robots with one robot_id: SPL017
    modes = _possible_modes(line)
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


def _possible_modes(line: ProductLine) -> dict[int, set[str]]:
    """The sharing modes a node can have in each container, by container id."""
    Node = tsm().Node
    modes: dict[int, set[str]] = defaultdict(set)
    for container in line.tsm.containers:
        for node in container.nodes:
            modes[id(container)].add(sharing_mode(node))
    chosen = _chosen_modes(line)
    for element in line.rm.elements:
        config = element.feature.sharing
        used: list[Any] = list(element.required)
        moved: list[tuple[Any, Any]] = []
        for transformation in element.transformations:
            kind = transformation.eClass.name
            if kind in ("Implementation", "NodeMigration"):
                used.append(transformation.node)
            if kind == "NodeMigration":
                moved.append((transformation.node, transformation.target))
        for node, target in moved:
            modes[id(target)].add(sharing_mode(node))
        if config is None:
            continue
        feature_modes = {config.mode.name} | chosen[element.feature.name]
        for node in used:
            if isinstance(node, Node):  # not a store
                modes[id(node.eContainer())] |= feature_modes
        for _, target in moved:
            modes[id(target)] |= feature_modes
    return modes


def _chosen_modes(line: ProductLine) -> dict[str, set[str]]:
    """The sharing modes the listed products choose, by feature (a product that does not
    load is SPL015's)."""
    chosen: dict[str, set[str]] = defaultdict(set)
    for path in line.product_files():
        try:
            selection = load_selection_file(path)
        except ModelError:
            continue
        for feature, mode in selection.sharing.items():
            chosen[feature].add(mode)
    return chosen
