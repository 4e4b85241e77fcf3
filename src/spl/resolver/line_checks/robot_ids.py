"""SPL017: two robot containers of the template with one robot_id (or two differing only
in case).

Rapyuta tells robots apart by their robotID and the bundle names files after it
(``zenoh/<robot_id>.json5``), so every product that keeps both containers and sets
neither robot_id in its ``deployment`` fails to resolve. A warning, not an error: a line
deployed only as fleets, or whose products always set the ids, never uses the template's.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from spl.core.diagnostics import Diagnostic, location_of
from spl.resolver.resolution.product_line import ProductLine

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

SHARED_ROBOT_ID = "SPL017"


def shared_robot_ids(line: ProductLine) -> list[Diagnostic]:
    """A warning at each robot container whose robot_id an earlier one already has."""
    found = []
    first: dict[
        str, tsm_types.Container
    ] = {}  # robot_id in lower case -> the first container with it
    for container in line.tsm.containers:
        endpoint = container.endpoint if container.eClass.name == "RobotContainer" else None
        robot_id = endpoint.robotId if endpoint is not None else None
        if not robot_id:
            continue
        earlier = first.setdefault(robot_id.lower(), container)
        if earlier is not container:
            found.append(
                Diagnostic(
                    location_of(endpoint) or location_of(container),
                    f"robot container {container.name} has robot_id {robot_id!r}, as robot "
                    f"container {earlier.name} has {earlier.endpoint.robotId!r}: a product "
                    "keeping both fails to resolve unless its deployment sets another for one",
                    "warning",
                    SHARED_ROBOT_ID,
                )
            )
    return found
