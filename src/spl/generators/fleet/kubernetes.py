"""A fleet's ``kubernetes/`` and ``zenoh/``: every cloud instance of the fleet once.

Each robot of a fleet is resolved on its own; its private instances (``<C>_<robotID>``)
are its own, and its shared ones (``<C>_<group>``, ``<C>_public``) are the fleet's
shared instances (:class:`~spl.resolver.fleets.deployment.SharedInstance`), launched
with their nodes as their reference robots resolved them, whichever robots use them.
One Deployment per instance, as for a product (:mod:`spl.generators.kubernetes.manifests`).

The Zenoh configurations are computed over all the robots' architectures together
(:attr:`FleetInputs.transport <spl.generators.bundle.inputs.FleetInputs.transport>`,
computed once per fleet bundle): each robot routes under its own
namespace, and a shared instance gets one bridge per robot it serves, so every robot
reaches the fleet's shared instances through the one router and no robot sees another
robot's data. A fleet Zenoh cannot carry gets its instances without bridges and the
reason in ``kubernetes/README.md``; its ``zenoh/`` is then left out.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Diagnostic, ModelError
from spl.generators.bundle.inputs import FleetInputs
from spl.generators.kubernetes import manifests as kubernetes
from spl.generators.kubernetes.objects import Placed, render, title
from spl.generators.kubernetes.router import router_documents
from spl.generators.launch import ros2_launch
from spl.generators.workloads.names import CONFIG_SUFFIX, ROUTER, ObjectNames
from spl.generators.workloads.network_policy import zenoh_connections
from spl.generators.zenoh import configurations as zenoh
from spl.resolver.architecture.placement import Instance, Place, Placement
from spl.resolver.fleets.deployment import FleetDeployment, SharedInstance

if TYPE_CHECKING:
    from spl.core.diagnostics import Location
    from spl.metamodels import tsm_types
    from spl.resolver.architecture.product import ResolvedProduct
    from spl.resolver.fleets.fleet import RobotProduct


def _shared_instance(
    deployment: FleetDeployment, instance: SharedInstance
) -> tuple[ResolvedProduct, Instance]:
    """The shared instance as placed (its nodes as their reference robots resolved them),
    and the product of its first reference robot."""
    reference = deployment.reference(instance)
    container = cast("tsm_types.CloudContainer", reference[0][1].eContainer())  # a cloud's
    place = Place(instance.tag, instance.mode, instance.container, instance.group or "public")
    nodes = tuple(node for _, node in reference)
    return reference[0][0].product, Instance(place, container, nodes, instance.robots)


def _private_instances(entry: RobotProduct) -> list[Instance]:
    """The robot's private cloud instances, one per cloud container it uses."""
    errors: list[Diagnostic] = []
    placement = Placement(entry.product.system, errors)
    instances = [i for i in placement.cloud_instances() if i.place.kind == "private"]
    if errors:
        raise ModelError(errors)
    return instances


def _instances(
    deployment: FleetDeployment,
) -> list[tuple[ResolvedProduct, Instance, str | None, Location | None]]:
    """(product, instance, robot name or None, location) of every instance of the fleet:
    the shared ones first, then each robot's private ones."""
    located = {entry.robot.name: entry.robot.location for entry in deployment.robots}
    found: list[tuple[ResolvedProduct, Instance, str | None, Location | None]] = []
    for shared in deployment.shared:
        product, instance = _shared_instance(deployment, shared)
        found.append((product, instance, None, located.get(shared.robots[0])))
    for entry in deployment.robots:
        for instance in _private_instances(entry):
            found.append((entry.product, instance, entry.robot.name, entry.robot.location))
    return found


def fleet_files(
    inputs: FleetInputs,
    per_robot: dict[str, list[str]],
    per_instance: dict[str, list[str]],
) -> dict[str, bytes]:
    """``kubernetes/`` and ``zenoh/`` of the fleet, in the namespace its options give,
    from its one transport; each instance's manifest is listed with its robot
    (``per_robot``) or shared instance (``per_instance``)."""
    deployment = inputs.deployment
    fleet = deployment.check.fleet.name
    instances = _instances(deployment)
    errors: list[Diagnostic] = []
    names = ObjectNames(errors, len(CONFIG_SUFFIX), (ROUTER,))
    named = [names.name(i.place.tag, where, "cloud instance") for _, i, _, where in instances]
    if errors:
        raise ModelError(errors)
    wiring = inputs.transport
    namespace = inputs.options.namespace_of(fleet)
    tags = {i.place.tag: name for (_, i, _, _), name in zip(instances, named, strict=True)}
    connections = zenoh_connections(wiring, tags)
    files: dict[str, bytes] = {
        "kubernetes/namespace.yaml": kubernetes.namespace_file(fleet, namespace, "fleet")
    }
    for (product, instance, robot, _), name in zip(instances, named, strict=True):
        launch = ros2_launch.launch_file(
            product,
            instance.container,
            instance.nodes,
            kubernetes.launch_header(instance.place.tag),
        )
        bridges = tuple(wiring.cloud_bridges.get(instance.place.tag, ())) if wiring.carried else ()
        path = f"kubernetes/{name}.yaml"
        # the robots' data services are each in their own product's namespace
        # (robots/<robot>/deploy/), so the fleet's instances connect to Zenoh only
        placed = Placed(namespace, product, connections)
        files[path] = kubernetes.instance_file(
            fleet, instance, name, launch, placed, bridges, "fleet", inputs.memo.plain
        )
        if robot is None:
            per_instance.setdefault(instance.place.tag, []).append(path)
        else:
            per_robot[robot].append(path)
    if wiring.routed:
        documents = router_documents(fleet, wiring, Placed(namespace, None, connections))
        files[f"kubernetes/{ROUTER}.yaml"] = render(
            documents, title(fleet, "Zenoh router", "fleet"), inputs.memo.plain
        )
    files["kubernetes/kustomization.yaml"] = kubernetes.kustomization(
        [path.removeprefix("kubernetes/") for path in files]
    )
    rows = sorted(
        ((name, instance) for (_, instance, _, _), name in zip(instances, named, strict=True)),
        key=lambda row: row[0],
    )
    note = kubernetes.transport_note(wiring)
    files["kubernetes/README.md"] = kubernetes.readme(f"fleet {fleet}", rows, note, namespace)
    if wiring.carried:
        files.update(zenoh.folder(f"fleet {fleet}", wiring))
    return files
