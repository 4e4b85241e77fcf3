"""Generator of the robot-side writer and reader nodes (seeds/000's WriteRTC/ReadRTC).

Each ``writer``/``reader`` of a robot container becomes ``clients/<package>/``, a ROS 2
ament_python package: an rclpy node wrapping a plain-HTTP module (``store_client``)
that the tests run against the real generated service. The message class comes from
the topic the node's ``records`` interface is connected to.
"""

from __future__ import annotations

import re
from typing import Any

from spl.diagnostics import Diagnostic, ModelError, location_of
from spl.generators.bundle_paths import BundleFiles
from spl.generators.jinja_templates import render
from spl.generators.store_contract import store_context
from spl.resolver.data_clients import client_package_name, client_packages
from spl.resolver.generated_names import IDENTIFIER, snake_case
from spl.resolver.product import ResolvedProduct

ROS_PACKAGE = re.compile(r"[a-z][a-z0-9_]*\Z")
MESSAGE_TYPE = re.compile(r"([A-Za-z][A-Za-z0-9_]*)/(?:msg/)?([A-Za-z][A-Za-z0-9_]*)\Z")
DEFAULT_STORE_URL = "http://localhost:8000"
KINDS = {
    "Writer": ("writer", "Subscriber", "writer_node"),
    "Reader": ("reader", "Publisher", "reader_node"),
}


def client_nodes(system: Any) -> list[tuple[Any, Any]]:
    """(container, node) for every writer and reader in a robot container."""
    return [
        (container, node)
        for container in system.containers
        if container.eClass.name == "RobotContainer"
        for node in container.nodes
        if node.eClass.name in KINDS
    ]


def _message(node: Any, interface_kind: str) -> tuple[str, str, str]:
    interface = next(
        (i for i in node.interfaces if i.eClass.name == interface_kind and i.name == "records"),
        None,
    )
    if interface is None:
        raise ModelError(
            [
                Diagnostic(
                    location_of(node),
                    f"{node.name}: no {interface_kind.lower()} interface 'records'",
                )
            ]
        )
    topic = getattr(interface, "topic", None)
    type_text = (topic.type if topic is not None and topic.type else interface.type) or ""
    match = MESSAGE_TYPE.match(type_text)
    if match is None:
        raise ModelError(
            [Diagnostic(location_of(interface), f"{node.name}: invalid message type {type_text!r}")]
        )
    return type_text, match.group(1), match.group(2)


def package_of(node: Any, generated: dict[int, str]) -> str:
    """The client package of ``node``: the Resolution Engine names it in the node (launch
    files start it); a model built without the engine gets the one it would name."""
    if ROS_PACKAGE.match(node.package or ""):
        return node.package
    return generated.get(id(node)) or client_package_name(node.name)


def generate_client(
    container: Any, node: Any, product: ResolvedProduct, package: str
) -> dict[str, bytes]:
    if not IDENTIFIER.match(node.name or ""):
        raise ModelError([Diagnostic(location_of(node), f"invalid node name {node.name!r}")])
    kind, interface_kind, module = KINDS[node.eClass.name]
    msg_type, msg_package, msg_name = _message(node, interface_kind)
    store = node.store
    executable = node.executable if ROS_PACKAGE.match(node.executable or "") else package
    refined_names = [r.output.name for r in store.refinements if r.output is not None]
    if kind == "writer" and node.dataType is not store.raw:
        raise ModelError(
            [
                Diagnostic(
                    location_of(node),
                    (
                        f"{node.name} writes {node.dataType.name}, but store {store.name} "
                        f"keeps {store.raw.name}"
                    ),
                )
            ]
        )
    if kind == "reader" and node.dataType.name not in refined_names:
        raise ModelError(
            [
                Diagnostic(
                    location_of(node),
                    (
                        f"{node.name} reads {node.dataType.name}, which store {store.name} "
                        f"does not refine (it refines {', '.join(refined_names) or 'nothing'})"
                    ),
                )
            ]
        )
    fields = {f.name: f.type.name for f in node.dataType.fields}
    for name in fields:
        if not IDENTIFIER.match(name):
            raise ModelError([Diagnostic(location_of(node), f"invalid field name {name!r}")])
    robot_id = (container.endpoint.robotId if container.endpoint is not None else None) or ""
    if not re.fullmatch(r"[A-Za-z0-9_.\-]{1,64}", robot_id):
        robot_id = snake_case(container.name)
    context = {
        "node": {"name": node.name, "kind": kind, "class_name": f"{node.name}Node"},
        "store": store_context(store, product),
        "msg": {"type": msg_type, "package": msg_package, "name": msg_name},
        "package": package,
        "executable": executable,
        "module": module,
        "collection": node.dataType.name if kind == "reader" else "records",
        "fields": fields,
        "robot_id": robot_id,
        "default_url": DEFAULT_STORE_URL,
        "period": float(node.period) if kind == "reader" and node.period else 1.0,
    }
    root = f"clients/{package}"
    return {
        f"{root}/package.xml": render("clients/package.xml.j2", **context),
        f"{root}/setup.py": render("clients/setup.py.j2", **context),
        f"{root}/setup.cfg": render("clients/setup.cfg.j2", **context),
        f"{root}/README.md": render("clients/README.md.j2", **context),
        f"{root}/resource/{package}": b"",
        f"{root}/{package}/__init__.py": render("clients/package/__init__.py.j2", **context),
        f"{root}/{package}/store_client.py": render(
            "clients/package/store_client.py.j2", **context
        ),
        f"{root}/{package}/{module}.py": render(f"clients/package/{module}.py.j2", **context),
    }


def generate(product: ResolvedProduct) -> dict[str, bytes]:
    """``clients/<package>/...`` for every writer and reader of the product; two that
    the model gives one package are refused (located), never folded into one folder."""
    files = BundleFiles()
    generated = client_packages(product.system)
    owners: dict[str, Any] = {}
    for container, node in client_nodes(product.system):
        package = package_of(node, generated)
        first = owners.setdefault(package, node)
        if first is not node:
            raise ModelError(
                [
                    Diagnostic(
                        location_of(node),
                        (
                            f"{node.name} and {first.name} ({location_of(first)}) both run package "
                            f"{package}: give one of them another implementation"
                        ),
                    )
                ]
            )
        files.update(generate_client(container, node, product, package))
    return files
