"""SPL018: a robot container whose endpoint lacks what the rce-ros client needs.

Every bundle has a Rapyuta configuration per robot container, and the client cannot log
in without the engine's url, a userID, a password and a robotID. A product's
``deployment`` may set the robot_id and the url, never the user or the password (they are
the line's, and the password only ever names a variable). So a missing user or password
fails every product keeping the container (an error), a missing robot_id or url every
product that does not set it (a warning).
"""

from __future__ import annotations

from spl.diagnostics import Diagnostic, location_of
from spl.resolver.product_line import ProductLine

INCOMPLETE_ENDPOINT = "SPL018"


def incomplete_endpoints(line: ProductLine) -> list[Diagnostic]:
    found = []
    for container in line.tsm.containers:
        if container.eClass.name != "RobotContainer":
            continue
        endpoint = container.endpoint
        where = location_of(endpoint) or location_of(container)
        missing = [
            setting
            for setting, value in (("user", endpoint.user), ("password env", endpoint.passwordEnv))
            if not value
        ]
        if missing:
            found.append(
                Diagnostic(
                    where,
                    f"robot container {container.name}: its endpoint has no "
                    f"{' and no '.join(missing)}: every product keeping it fails to resolve "
                    "(the rce-ros client needs them, and a deployment cannot set them)",
                    "error",
                    INCOMPLETE_ENDPOINT,
                )
            )
        unset = [
            setting
            for setting, value in (("robot_id", endpoint.robotId), ("url", endpoint.url))
            if not value
        ]
        if unset:
            found.append(
                Diagnostic(
                    where,
                    f"robot container {container.name}: its endpoint has no "
                    f"{' and no '.join(unset)}: every product keeping it must set "
                    f"{'them' if len(unset) > 1 else 'it'} in its deployment",
                    "warning",
                    INCOMPLETE_ENDPOINT,
                )
            )
    return found
