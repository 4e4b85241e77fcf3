"""NetworkPolicies from the resolved architecture: least privilege, per workload
(docs/kubernetes.md, "What the policies allow").

Each namespace denies all traffic in and out (``default-deny``) but DNS lookups to the
cluster's DNS in ``kube-system`` (``allow-dns``). Then each workload gets one policy
that allows exactly the connections the resolved architecture makes, on their ports,
and nothing else:

- robots dial the Zenoh router on its port (from outside the cluster: any source), when
  some robot's bridge connects to it;
- the router dials each bridge of each cloud instance on that bridge's port: the
  bridges :mod:`spl.generators.transport.bridge` derives from the crossing flows of the flow
  table (:mod:`spl.resolver.architecture.wiring`), so an instance no flow reaches gets no ingress;
- a writer or reader calls its store's data service on the service's port: from
  outside when it runs on a robot, from its cloud instance's pods when it runs there;
- a data service connects to PostgreSQL when the product stores in it.

A :class:`Connection` is one such allowed pair; the policy of a workload is made of the
connections it is an end of, so the two ends of a pair always agree.
"""

from __future__ import annotations

from typing import NamedTuple

from spl.core.diagnostics import Diagnostic, ModelError
from spl.generators.json_text import Document
from spl.generators.transport.bridge import ZENOH_PORT, Transport
from spl.generators.workloads.names import ROUTER, dns_label
from spl.metamodels import tsm
from spl.resolver.architecture.placement import Placement
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.stores import cloud_stores, database_kind, store_names

WORLD = ""  # outside the cluster: robots, whose traffic comes through a load balancer
SERVICE_PORT = 8000  # a data service's container port (HTTPS in the cluster)
POSTGRES = "postgres"
POSTGRES_PORT = 5432
NAME_LABEL = "app.kubernetes.io/name"
DEFAULT_DENY = "default-deny"
ALLOW_DNS = "allow-dns"


class Connection(NamedTuple):
    """``source`` (a workload's name, or :data:`WORLD`) may open TCP connections to the
    pods of workload ``target`` on container port ``port``."""

    source: str
    target: str
    port: int


def zenoh_connections(wiring: Transport, names: dict[str, str]) -> list[Connection]:
    """Robots to the router, the router to every bridge of every cloud instance
    (``names``: placement tag -> object name)."""
    if not wiring.routed:
        return []
    found = [Connection(WORLD, ROUTER, ZENOH_PORT)] if wiring.robot_configs else []
    for tag, bridges in sorted(wiring.cloud_bridges.items()):
        found.extend(Connection(ROUTER, names[tag], bridge.port) for bridge in bridges)
    return found


def store_connections(product: ResolvedProduct) -> list[Connection]:
    """Writers and readers to their stores' services, the services to PostgreSQL."""
    system = product.system
    stores = cloud_stores(system)
    if not stores:
        return []
    T = tsm()
    names = store_names(system)
    dns = {id(store): names[id(store)].dns for store in stores}
    errors: list[Diagnostic] = []
    placement = Placement(system, errors, flows=product.flows)
    instances = placement.cloud_instances()
    if errors:
        raise ModelError(errors)
    found: list[Connection] = []
    for container in system.containers:
        for node in container.nodes:
            if not isinstance(node, T.Writer | T.Reader) or id(node.store) not in dns:
                continue
            target = dns[id(node.store)]
            if placement.is_robot(container):
                found.append(Connection(WORLD, target, SERVICE_PORT))
                continue
            found.extend(
                Connection(dns_label(instance.place.tag), target, SERVICE_PORT)
                for instance in instances
                if any(n is node for n in instance.nodes)
            )
    if database_kind(product) == "postgresql":
        found.extend(Connection(dns[id(store)], POSTGRES, POSTGRES_PORT) for store in stores)
    return sorted(set(found))


def _selector(name: str) -> Document:
    return {"podSelector": {"matchLabels": {NAME_LABEL: name}}}


def _rules(peers: dict[str, set[int]], direction: str) -> list[Document]:
    rules: list[Document] = []
    for peer in sorted(peers):
        ports = [{"protocol": "TCP", "port": port} for port in sorted(peers[peer])]
        rule: Document = {direction: [_selector(peer)]} if peer != WORLD else {}
        rule["ports"] = ports
        rules.append(rule)
    return rules


def workload_policy(
    name: str, namespace: str, labels: dict[str, str], connections: list[Connection]
) -> Document:
    """The NetworkPolicy of workload ``name``: ingress from and egress to exactly the
    peers ``connections`` give it, on their ports (none: nothing in or out)."""
    incoming: dict[str, set[int]] = {}
    outgoing: dict[str, set[int]] = {}
    for connection in connections:
        if connection.target == name:
            incoming.setdefault(connection.source, set()).add(connection.port)
        if connection.source == name:
            outgoing.setdefault(connection.target, set()).add(connection.port)
    return {
        "apiVersion": "networking.k8s.io/v1",
        "kind": "NetworkPolicy",
        "metadata": {"name": name, "namespace": namespace, "labels": labels},
        "spec": {
            "podSelector": {"matchLabels": {NAME_LABEL: name}},
            "policyTypes": ["Ingress", "Egress"],
            "ingress": _rules(incoming, "from"),
            "egress": _rules(outgoing, "to"),
        },
    }


def namespace_policies(namespace: str, labels: dict[str, str]) -> list[Document]:
    """``default-deny`` (every pod, in and out) and ``allow-dns`` (every pod to the
    cluster DNS in kube-system, UDP and TCP 53)."""
    deny: Document = {
        "apiVersion": "networking.k8s.io/v1",
        "kind": "NetworkPolicy",
        "metadata": {"name": DEFAULT_DENY, "namespace": namespace, "labels": labels},
        "spec": {"podSelector": {}, "policyTypes": ["Ingress", "Egress"]},
    }
    dns: Document = {
        "apiVersion": "networking.k8s.io/v1",
        "kind": "NetworkPolicy",
        "metadata": {"name": ALLOW_DNS, "namespace": namespace, "labels": labels},
        "spec": {
            "podSelector": {},
            "policyTypes": ["Egress"],
            "egress": [
                {
                    "to": [
                        {
                            "namespaceSelector": {
                                "matchLabels": {"kubernetes.io/metadata.name": "kube-system"}
                            },
                            "podSelector": {"matchLabels": {"k8s-app": "kube-dns"}},
                        }
                    ],
                    "ports": [{"protocol": "UDP", "port": 53}, {"protocol": "TCP", "port": 53}],
                }
            ],
        },
    }
    return [deny, dns]
