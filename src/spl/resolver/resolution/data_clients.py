"""Writers and readers the models leave unimplemented run the ROS package spl generates
for them (``clients/<package>`` in the bundle). Naming that package is a resolution
decision: the resolved model states ``package/executable`` like for any other node, and
the generators only read it.

A node's name is unique only in its container, and every client package of a product
lands in one ``clients/`` folder (and one ROS workspace): two robot containers' writers
``PositionWriter`` get ``<container>_position_writer`` packages, any other writer keeps
``position_writer`` (:func:`spl.resolver.architecture.generated_names.unique_names`).
"""

from __future__ import annotations

import keyword
from typing import TYPE_CHECKING

from spl.metamodels import tsm
from spl.resolver.architecture.generated_names import lower_identifier, unique_names

if TYPE_CHECKING:
    from spl.metamodels import tsm_types


def client_package_name(node_name: str) -> str:
    """ROS package and executable of a writer/reader: ``PositionWriter`` -> ``position_writer``;
    a Python keyword gets ``_client`` (``Import`` -> ``import_client``): the package is a
    Python package, and ``from import.reader_node import main`` does not parse."""
    package = lower_identifier(node_name, "client")
    return f"{package}_client" if keyword.iskeyword(package) else package


def _package_form(node: tsm_types.Node, name: str) -> set[str]:
    return {client_package_name(name)}


def client_packages(system: tsm_types.System) -> dict[int, str]:
    """The generated package of every writer and reader of ``system`` that the models
    leave unimplemented (by ``id``), unique across the system and apart from the
    packages other writers and readers name."""
    T = tsm()
    clients = [
        (node, container.name, node.name)
        for container in system.containers
        for node in container.nodes
        if isinstance(node, T.Writer | T.Reader)
    ]
    named = frozenset(node.package for node, _, _ in clients if node.package)
    open_clients = [client for client in clients if not client[0].package]
    names = unique_names(open_clients, _package_form, named)
    return {
        id(node): client_package_name(name)
        for (node, _, _), name in zip(open_clients, names, strict=True)
    }


def implement_data_clients(system: tsm_types.System) -> None:
    """Writers and readers run the ROS package generated for them (clients/<package>)."""
    packages = client_packages(system)
    for container in system.containers:
        for node in container.nodes:
            package = packages.get(id(node))
            if package is not None:
                node.package, node.executable = package, package
