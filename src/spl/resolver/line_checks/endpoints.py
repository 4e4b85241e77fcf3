"""SPL018: a robot container whose endpoint lacks what the rce-ros client needs.

Every bundle has a Rapyuta configuration per robot container, and the client cannot log
in without the engine's url, a userID, a password and a robotID. A product's
``deployment`` may set the robot_id and the url, never the user or the password (they are
the line's, and the password only ever names a variable). So a missing user or password
fails every product keeping the container (an error), a missing robot_id or url every
product that does not set it (a warning).
"""

from __future__ import annotations

from spl.core.diagnostics import Diagnostic, Severity, location_of
from spl.resolver.resolution.product_line import ProductLine

INCOMPLETE_ENDPOINT = "SPL018"


# (the settings, by their .tsm name and attribute), severity, what follows when one is missing
RULES: tuple[tuple[tuple[tuple[str, str], ...], Severity, str], ...] = (
    (
        (("user", "user"), ("password env", "passwordEnv")),
        "error",
        "every product keeping it fails to resolve (the rce-ros client needs {them}, and a "
        "deployment cannot set {them})",
    ),
    (
        (("robot_id", "robotId"), ("url", "url")),
        "warning",
        "every product keeping it must set {them} in its deployment",
    ),
)


def incomplete_endpoints(line: ProductLine) -> list[Diagnostic]:
    found = []
    for container in line.tsm.containers:
        if container.eClass.name != "RobotContainer":
            continue
        endpoint = container.endpoint
        where = location_of(endpoint) or location_of(container)
        for settings, severity, consequence in RULES:
            missing = [name for name, attribute in settings if not getattr(endpoint, attribute)]
            if missing:
                them = "them" if len(missing) > 1 else "it"
                found.append(
                    Diagnostic(
                        where,
                        f"robot container {container.name}: its endpoint has no "
                        f"{' and no '.join(missing)}: {consequence.format(them=them)}",
                        severity,
                        INCOMPLETE_ENDPOINT,
                    )
                )
    return found
