"""The four transformation kinds of seeds/003, one module each.

``APPLY`` maps a transformation's metaclass name to the function that applies it to
the product being derived; the engine runs them in file order.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from spl.resolver.transformations import connect, implementation, migration, parameter

APPLY: dict[str, Callable[[Any, Any], None]] = {
    "Implementation": implementation.apply,
    "ConnectToTopic": connect.to_topic,
    "ConnectToNewTopic": connect.to_new_topic,
    "ConnectService": connect.to_server,
    "ConnectBridge": connect.bridge,
    "ParameterValue": parameter.apply,
    "NodeMigration": migration.apply,
}
