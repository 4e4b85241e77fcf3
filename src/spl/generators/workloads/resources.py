"""CPU and memory of every generated container, and the probes that test it
(docs/kubernetes.md, "Resources and probes").

A scheduler places a pod by its requests and a node survives a runaway process by its
limits, so every container gets both: from the model where it says them, else from the
defaults of :data:`DEFAULTS`, one row per kind of workload.

- A cloud instance's ROS container takes its TSM container's ``cpu`` (cores) and
  ``memory`` (MiB) as request and limit, as the Rapyuta files do.
- Any workload kind ``K`` (``ros``, ``bridge``, ``router``, ``service``, ``postgres``)
  takes a selected feature's attributes ``K_cpu`` (cores, a number) and ``K_memory``
  (MiB, a whole number) as request and limit: ``attribute service_memory : int = 512``
  in the feature model gives every data service 512 MiB.

A probe must fail when the workload cannot do its job, not merely when its process is
gone: the ROS container is ready when every node of its launch file is in its ROS 2
graph (``ros2 node list``); a Zenoh bridge or router when its admin space answers over
its REST plugin; a data service is ready when its root, which makes a round trip to
the database, answers, and alive while it serves its OpenAPI document;
PostgreSQL when ``pg_isready`` says it accepts connections.
"""

from __future__ import annotations

import shlex
from typing import NamedTuple

from spl.core.diagnostics import Diagnostic, ModelError
from spl.generators.json_text import Document
from spl.resolver.architecture.product import ResolvedProduct

KINDS = ("ros", "bridge", "router", "service", "postgres")


class Amounts(NamedTuple):
    """Requests and limits of one container: CPU in millicores, memory in MiB."""

    cpu_request: int
    memory_request: int
    cpu_limit: int
    memory_limit: int


DEFAULTS = {
    "ros": Amounts(250, 256, 1000, 1024),
    "bridge": Amounts(50, 64, 500, 256),
    "router": Amounts(100, 64, 1000, 256),
    "service": Amounts(100, 128, 1000, 512),
    "postgres": Amounts(250, 256, 1000, 1024),
}
# the admin space of a Zenoh node through its REST plugin: every router's entry
ADMIN_PATH = "/@/*/router"
FIRST_ADMIN_PORT = 8000


def _cpu(millicores: int) -> str:
    return str(millicores // 1000) if millicores % 1000 == 0 else f"{millicores}m"


def _document(amounts: Amounts) -> Document:
    return {
        "requests": {
            "cpu": _cpu(amounts.cpu_request),
            "memory": f"{amounts.memory_request}Mi",
        },
        "limits": {"cpu": _cpu(amounts.cpu_limit), "memory": f"{amounts.memory_limit}Mi"},
    }


def _attribute(product: ResolvedProduct | None, name: str) -> tuple[str, object] | None:
    """(``Feature.name``, value) of a selected feature's attribute ``name``, if any."""
    if product is None:
        return None
    selected = set(product.features)
    for key, value in sorted(product.attributes.items()):
        feature, _, attribute = key.rpartition(".")
        if attribute == name and feature in selected:
            return key, value
    return None


def _millicores(key: str, value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, int | float) or not 0 < value <= 1024:
        raise ModelError(
            [
                Diagnostic(
                    None, f"attribute {key} = {value!r}: CPU must be a number of cores in (0, 1024]"
                )
            ]
        )
    return max(1, round(value * 1000))


def _mebibytes(key: str, value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 < value <= 2**20:
        raise ModelError(
            [
                Diagnostic(
                    None, f"attribute {key} = {value!r}: memory must be whole MiB in 1..1048576"
                )
            ]
        )
    return value


def resources(
    kind: str,
    product: ResolvedProduct | None = None,
    cpu: float | None = None,
    memory: int | None = None,
) -> Document:
    """Requests and limits of a ``kind`` container: ``cpu``/``memory`` given by the model
    (a TSM container's), else the selected features' ``<kind>_cpu``/``<kind>_memory``
    attributes, each as request and limit, else the kind's defaults."""
    base = DEFAULTS[kind]
    cpu_request, cpu_limit = base.cpu_request, base.cpu_limit
    memory_request, memory_limit = base.memory_request, base.memory_limit
    found = _attribute(product, f"{kind}_cpu")
    if cpu is not None:
        cpu_request = cpu_limit = _millicores("cpu", cpu)
    elif found is not None:
        cpu_request = cpu_limit = _millicores(*found)
    found = _attribute(product, f"{kind}_memory")
    if memory is not None:
        memory_request = memory_limit = _mebibytes("memory", memory)
    elif found is not None:
        memory_request = memory_limit = _mebibytes(*found)
    return _document(Amounts(cpu_request, memory_request, cpu_limit, memory_limit))


def ros_node_names(namespace: str | None, nodes: list[str]) -> list[str]:
    """The fully qualified ROS 2 names the nodes of a launch file register with."""
    prefix = "/" + namespace.strip("/") if namespace and namespace.strip("/") else ""
    return [f"{prefix}/{name}" for name in nodes]


def ros_probes(names: list[str]) -> Document:
    """Readiness and liveness of a ROS 2 container: every node in ``names`` is in the
    graph ``ros2 node list`` sees (without the daemon, which would outlive the probe),
    run through the image's entrypoint, which sources the ROS installation."""
    checks = " ".join(shlex.quote(name) for name in names)
    script = (
        "names=$(ros2 node list --no-daemon --spin-time 3) && "
        f'for node in {checks}; do printf "%s\\n" "$names" | grep -qxF "$node" || exit 1; done'
    )
    command = ["/ros_entrypoint.sh", "/bin/sh", "-c", script]
    return {
        "readinessProbe": {
            "exec": {"command": command},
            "initialDelaySeconds": 10,
            "periodSeconds": 20,
            "timeoutSeconds": 15,
        },
        "livenessProbe": {
            "exec": {"command": command},
            "initialDelaySeconds": 60,
            "periodSeconds": 60,
            "timeoutSeconds": 15,
            "failureThreshold": 3,
        },
    }


def admin_port_name(index: int) -> str:
    """The container port of a Zenoh node's REST plugin (``admin``, ``admin-2``, ...)."""
    return "admin" if index == 0 else f"admin-{index + 1}"


def zenoh_probes(port: str) -> Document:
    """Readiness and liveness of a Zenoh bridge or router: its admin space answers a
    GET through the REST plugin listening on container port ``port``."""
    check = {"httpGet": {"path": ADMIN_PATH, "port": port}, "timeoutSeconds": 5}
    return {
        "readinessProbe": {**check, "periodSeconds": 10},
        "livenessProbe": {**check, "initialDelaySeconds": 20, "periodSeconds": 30},
    }
