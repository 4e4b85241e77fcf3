"""The Zenoh router's Kubernetes objects (docs/deployment.md, "Kubernetes and Zenoh
bridges"; docs/kubernetes.md for what it runs with).

The router (``zenohd``) robots connect to: a ``LoadBalancer`` Service on port 7447, and
it connects to every cloud instance's bridges. Robots authenticate with their
endpoint's user and the password named by ``password env "VAR"``: the router reads the
passwords from the Secret ``zenoh-router-credentials`` mounted read-only as files (one
key per variable, never an environment variable a crash dump or ``kubectl describe``
shows) and writes, at start, the dictionary file zenohd takes into memory-backed
storage. Its REST plugin answers the probes from the admin space.
"""

from __future__ import annotations

from spl.generators.json_text import Document
from spl.generators.kubernetes.objects import (
    CONFIG_DIR,
    MANAGED_BY,
    ROUTER_IMAGE,
    Placed,
    _Literal,
    service,
)
from spl.generators.transport.bridge import ZENOH_PORT, Transport
from spl.generators.workloads.names import CONFIG_SUFFIX, ROUTER, label_value
from spl.generators.workloads.network_policy import workload_policy
from spl.generators.workloads.resources import (
    FIRST_ADMIN_PORT,
    admin_port_name,
    resources,
    zenoh_probes,
)
from spl.generators.workloads.security import harden, waiver_annotations

SECRETS_DIR = "/run/secrets/zenoh-router"


def secret_name() -> str:
    """The Secret holding the robots' passwords, one key per ``password env`` variable."""
    return f"{ROUTER}-credentials"


def secret_key(variable: str) -> str:
    """A Secret key for an environment variable (keys allow ``A-Z a-z 0-9 - _ .``)."""
    return variable.lower().replace("_", "-")


def router_documents(product_name: str, wiring: Transport, placed: Placed) -> list[Document]:
    """ConfigMap, Deployment, NetworkPolicy and Service of the Zenoh router robots
    connect to, with its users' passwords from the Secret's files."""
    namespace = placed.namespace
    labels = {
        "app.kubernetes.io/name": ROUTER,
        "app.kubernetes.io/part-of": label_value(product_name),
        **MANAGED_BY,
    }
    config_map: Document = {
        "apiVersion": "v1",
        "kind": "ConfigMap",
        "metadata": {"name": ROUTER + CONFIG_SUFFIX, "namespace": namespace, "labels": labels},
        "data": {"zenoh-router.json5": _Literal(wiring.router_config)},
    }
    # The router reads its users from a dictionary file ("user:password" lines), written
    # at start from the Secret's files into memory-backed storage.
    lines = " ".join(
        f"'{user}' \"$(cat {SECRETS_DIR}/{secret_key(variable)})\""
        for user, variable in wiring.credentials
    )
    run = f"exec /zenohd -c {CONFIG_DIR}/zenoh-router.json5 --rest-http-port {FIRST_ADMIN_PORT}"
    start = f"printf '%s:%s\\n' {lines} > /run/zenoh/users && {run}" if lines else run
    mounts = [
        {"name": "config", "mountPath": CONFIG_DIR, "readOnly": True},
        {"name": "users", "mountPath": "/run/zenoh"},
    ]
    volumes: list[Document] = [
        {"name": "config", "configMap": {"name": ROUTER + CONFIG_SUFFIX}},
        {"name": "users", "emptyDir": {"medium": "Memory", "sizeLimit": "1Mi"}},
    ]
    if wiring.credentials:
        mounts.append({"name": "credentials", "mountPath": SECRETS_DIR, "readOnly": True})
        volumes.append(
            {
                "name": "credentials",
                "secret": {"secretName": secret_name(), "defaultMode": 0o440},
            }
        )
    admin = admin_port_name(0)
    container: Document = {
        "name": "zenohd",
        "image": ROUTER_IMAGE,
        "command": ["/bin/sh", "-c", start],
        "ports": [
            {"name": "zenoh", "containerPort": ZENOH_PORT, "protocol": "TCP"},
            {"name": admin, "containerPort": FIRST_ADMIN_PORT, "protocol": "TCP"},
        ],
        "volumeMounts": mounts,
        "resources": resources("router", placed.product),
        **zenoh_probes(admin),
    }
    deployment: Document = {
        "apiVersion": "apps/v1",
        "kind": "Deployment",
        "metadata": {
            "name": ROUTER,
            "namespace": namespace,
            "labels": labels,
            "annotations": waiver_annotations(),
        },
        "spec": {
            "replicas": 1,
            "selector": {"matchLabels": {"app.kubernetes.io/name": ROUTER}},
            "template": {
                "metadata": {"labels": labels},
                "spec": harden({"containers": [container], "volumes": volumes}),
            },
        },
    }
    return [
        config_map,
        deployment,
        workload_policy(ROUTER, namespace, labels, placed.connections),
        service(ROUTER, namespace, labels, "LoadBalancer", [("zenoh", ZENOH_PORT)]),
    ]
