"""Writers and readers the models leave unimplemented run the ROS package spl generates
for them (``clients/<package>`` in the bundle). Naming that package is a resolution
decision: the resolved model states ``package/executable`` like for any other node, and
the generators only read it.
"""

from __future__ import annotations

from typing import Any

from spl.metamodels import tsm
from spl.resolver.generated_names import snake_case


def client_package_name(node_name: str) -> str:
    """ROS package and executable of a writer/reader: ``PositionWriter`` -> ``position_writer``."""
    return snake_case(node_name)


def data_client_implementation(node: Any) -> str | None:
    """``package/executable`` of a writer or reader the models leave unimplemented: the
    ROS package generated for it (clients/<package>); None for any other node."""
    T = tsm()
    if isinstance(node, (T.Writer, T.Reader)) and not node.package:
        name = client_package_name(node.name)
        return f"{name}/{name}"
    return None


def implement_data_clients(system: Any) -> None:
    """Writers and readers run the ROS package generated for them (clients/<package>)."""
    for container in system.containers:
        for node in container.nodes:
            implementation = data_client_implementation(node)
            if implementation is not None:
                node.package, node.executable = implementation.split("/")
