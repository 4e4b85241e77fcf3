"""Generator of the robot-side writer and reader nodes (docs/services.md, "Robot-side
writers and readers": the WriteRTC/ReadRTC of *Architecture and framework for data
acquisition in cloud robotics*).

Each ``writer``/``reader`` of a robot container becomes two packages of one node, one
per ROS flavour, both wrapping one plain-HTTP module (``store_client``: batching,
retries with back-off, idempotent writes) that the tests run against the real
generated service: ``clients/ros1/<package>/``, a catkin package with a rospy node
(the ROS 1 launch files start it, and ``spl smoke`` runs it), and
``clients/ros2/<package>/``, an ament_python package with an rclpy node. The message
class comes from the topic the node's ``records`` interface is connected to. What is
the same in every node is :mod:`spl.generators.clients.runtime`, copied byte for byte
into each package as ``<package>/runtime/`` (docs/services.md, "Robot-side writers and
readers"); ``store_client`` holds the product's names and passes them to it.
"""

from __future__ import annotations

import re
from importlib.resources import files as package_files
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Diagnostic, ModelError, location_of
from spl.generators.bundle.paths import BundleFiles
from spl.generators.jinja_templates import render
from spl.generators.store_contract import client_settings, store_context
from spl.metamodels.interface_kinds import TOPIC, InterfaceKind, kind_of, side
from spl.resolver.architecture.generated_names import IDENTIFIER
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.resolution.data_clients import client_package_name, client_packages

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

RUNTIME = "spl.generators.clients.runtime"  # shipped as <package>/runtime/
ROS_PACKAGE = re.compile(r"[a-z][a-z0-9_]*\Z")
MESSAGE_TYPE = re.compile(r"([A-Za-z][A-Za-z0-9_]*)/(?:msg/)?([A-Za-z][A-Za-z0-9_]*)\Z")
ROS2_TOP = ("package.xml", "setup.py", "setup.cfg", "README.md")
ROS1_TOP = ("package.xml", "CMakeLists.txt", "setup.py", "README.md")
# a writer takes the records it stores from a topic, a reader puts those it reads on one
KINDS = {
    "Writer": ("writer", side(TOPIC, False), "writer_node"),
    "Reader": ("reader", side(TOPIC, True), "reader_node"),
}


def client_nodes(
    system: tsm_types.System,
) -> list[tuple[tsm_types.Container, tsm_types.Writer | tsm_types.Reader]]:
    """(container, node) for every writer and reader in a robot container."""
    return [
        (container, cast("tsm_types.Writer | tsm_types.Reader", node))
        for container in system.containers
        if container.eClass.name == "RobotContainer"
        for node in container.nodes
        if node.eClass.name in KINDS
    ]


def _message(node: tsm_types.Node, interface_kind: InterfaceKind) -> tuple[str, str, str]:
    interface = next(
        (i for i in node.interfaces if kind_of(i) is interface_kind and i.name == "records"),
        None,
    )
    if interface is None:
        raise ModelError(
            [
                Diagnostic(
                    location_of(node),
                    f"{node.name}: no {interface_kind.eclass.lower()} interface 'records'",
                )
            ]
        )
    topic: tsm_types.Topic | None = interface_kind.bound_to(interface)
    type_text = (topic.type if topic is not None and topic.type else interface.type) or ""
    match = MESSAGE_TYPE.match(type_text)
    if match is None:
        raise ModelError(
            [Diagnostic(location_of(interface), f"{node.name}: invalid message type {type_text!r}")]
        )
    return type_text, match.group(1), match.group(2)


def listeners(node: tsm_types.Node, product: ResolvedProduct) -> int:
    """How many subscribers a reader waits for before it publishes (docs/services.md,
    "Robot-side writers and readers"): the nodes of its own ROS graph that the flow
    table delivers its records to, each a subscriber of the records topic there, and
    the container's endpoint once when some of them travel on over a bridge; at least
    one, since a record published to no subscriber reaches nobody."""
    publisher = next(i for i in node.interfaces if kind_of(i).publishes and i.name == "records")
    first_hops = {
        id((flow.route[0].source if flow.route else flow.target).eContainer())
        for flow in product.flows.at(publisher)
        if flow.source is publisher
    }
    return max(1, len(first_hops))


def package_of(node: tsm_types.Node, generated: dict[int, str]) -> str:
    """The client package of ``node``: the Resolution Engine names it in the node (launch
    files start it); a model built without the engine gets the one it would name."""
    if ROS_PACKAGE.match(node.package or ""):
        return node.package
    return generated.get(id(node)) or client_package_name(node.name)


def runtime_files() -> dict[str, bytes]:
    """The clients' runtime modules by file name, as they are in spl (copied, not
    rendered, as the service generator copies the services' runtime)."""
    found = {}
    for entry in package_files(RUNTIME).iterdir():
        if entry.name.endswith(".py") and entry.is_file():
            found[entry.name] = entry.read_bytes()
    return dict(sorted(found.items()))


def generate_client(
    container: tsm_types.Container,
    node: tsm_types.Writer | tsm_types.Reader,
    product: ResolvedProduct,
    package: str,
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
    settings = client_settings(container, node, product)
    names = store_context(store, product)
    context = {
        "node": {"name": node.name, "kind": kind, "class_name": f"{node.name}Node"},
        "store": names,
        "ca_env": f"{names['slug'].upper()}_CA_FILE",
        "subscribe": bool(getattr(node, "subscribe", False)),
        "msg": {"type": msg_type, "package": msg_package, "name": msg_name},
        "package": package,
        "executable": executable,
        "module": module,
        "collection": node.dataType.name if kind == "reader" else "records",
        "fields": fields,
        "robot_id": settings["robot_id"],
        "default_url": settings["default_url"],
        "period": settings["period"],
        "subscribers": listeners(node, product) if kind == "reader" else 0,
    }
    shared = {
        "__init__.py": render("clients/__init__.py.j2", **context),
        "store_client.py": render("clients/store_client.py.j2", **context),
    }
    shared |= {f"runtime/{name}": data for name, data in runtime_files().items()}
    ros2, ros1 = f"clients/ros2/{package}", f"clients/ros1/{package}"
    files = {f"{ros2}/{name}": render(f"clients/ros2/{name}.j2", **context) for name in ROS2_TOP}
    files[f"{ros2}/resource/{package}"] = b""
    files |= {f"{ros2}/{package}/{name}": text for name, text in shared.items()}
    files[f"{ros2}/{package}/{module}.py"] = render(
        f"clients/ros2/package/{module}.py.j2", **context
    )
    files |= {f"{ros1}/{name}": render(f"clients/ros1/{name}.j2", **context) for name in ROS1_TOP}
    files[f"{ros1}/scripts/{executable}"] = render("clients/ros1/script.j2", **context)
    files |= {f"{ros1}/src/{package}/{name}": text for name, text in shared.items()}
    files[f"{ros1}/src/{package}/{module}.py"] = render(
        f"clients/ros1/package/{module}.py.j2", **context
    )
    return files


def generate(product: ResolvedProduct) -> dict[str, bytes]:
    """``clients/ros1/<package>/`` and ``clients/ros2/<package>/`` for every writer and
    reader of the product; two that
    the model gives one package are refused (located), never folded into one folder."""
    files = BundleFiles()
    generated = client_packages(product.system)
    owners: dict[str, tsm_types.Node] = {}
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
