"""Generator of the cloud-side deployment files of the data-acquisition services.

``deploy/`` gets one Dockerfile per service, a docker-compose.yml running every
service (plus PostgreSQL when the product stores in PostgreSQL), and Kubernetes
manifests: a Deployment, Service and NetworkPolicy per store, and PostgreSQL as a
StatefulSet, in the product's namespace at the restricted Pod Security level
(docs/kubernetes.md). Secrets are only ever named: compose reads them from the
environment, Kubernetes from a Secret created out of band and mounted read-only as
files, which the services read through ``<VAR>_FILE``.
"""

from __future__ import annotations

from typing import TypedDict

import yaml

from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.paths import BundleFiles
from spl.generators.jinja_templates import render
from spl.generators.json_text import Document
from spl.generators.store_contract import StoreContext, store_context
from spl.generators.workloads.network_policy import (
    POSTGRES,
    SERVICE_PORT,
    Connection,
    store_connections,
    workload_policy,
)
from spl.generators.workloads.resources import resources
from spl.generators.workloads.security import (
    container_security,
    pod_security,
    waiver_annotations,
)
from spl.resolver.architecture.generated_names import dns_name
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.stores import cloud_stores, database_kind

FIRST_HOST_PORT = 8000
POSTGRES_IMAGE = "postgres:16"


class _Entry(TypedDict):
    """One store as the deployment templates take it."""

    store: StoreContext
    image: str
    host_port: int
    token_key: str


def _project(product: ResolvedProduct) -> str:
    name = product.name if isinstance(product.name, str) else ""
    cleaned = "".join(c if c.isalnum() or c == "_" else "_" for c in name).strip("_")
    return dns_name(cleaned) if cleaned and cleaned[0].isalpha() else "spl-product"


def _yaml(document: Document) -> str:
    """A document as block YAML, keys in the order built (no trailing line break)."""
    return yaml.safe_dump(document, sort_keys=False, default_flow_style=False).rstrip("\n")


def generate(product: ResolvedProduct, options: BundleOptions | None = None) -> dict[str, bytes]:
    """``deploy/`` of the product's cloud data stores (none without one); its Kubernetes
    manifests in the namespace ``options`` give (default ``spl resolve``'s)."""
    stores = cloud_stores(product.system)
    if not stores:
        return {}
    project = _project(product)
    namespace = (options or BundleOptions()).namespace_of(product.name)
    connections = store_connections(product)
    postgres = database_kind(product) == "postgresql"
    secret = f"{project}-secrets"
    entries: list[_Entry] = []
    for index, store in enumerate(stores):
        context = store_context(store, product)
        entries.append(
            {
                "store": context,
                "image": f"{project}/{context['dns']}:1.0.0",
                "host_port": FIRST_HOST_PORT + index,
                "token_key": f"{context['dns']}-token",
            }
        )
    common = {
        "product": product.name,
        "project": project,
        "postgres": postgres,
        "postgres_image": POSTGRES_IMAGE,
        "port": SERVICE_PORT,
        "secret": secret,
        "namespace": namespace,
        "waivers": waiver_annotations(),
        "pod_security": _yaml(pod_security()),
        "container_security": _yaml(container_security()),
        "service_resources": _yaml(resources("service", product)),
        "postgres_resources": _yaml(resources("postgres", product)),
    }
    files = BundleFiles(
        {
            "deploy/docker-compose.yml": render(
                "deploy/docker-compose.yml.j2", stores=entries, **common
            ),
            "deploy/README.md": render("deploy/README.md.j2", stores=entries, **common),
        }
    )
    for entry in entries:
        names = entry["store"]
        files[f"deploy/{names['name']}/Dockerfile"] = render(
            "deploy/Dockerfile.j2", store=names, **common
        )
        files[f"deploy/kubernetes/{names['dns']}.yaml"] = render(
            "deploy/service.k8s.yaml.j2",
            store=names,
            image=entry["image"],
            token_key=entry["token_key"],
            policy=_policy(names["dns"], project, namespace, connections),
            **common,
        )
    if postgres:
        files["deploy/kubernetes/postgres.yaml"] = render(
            "deploy/postgres.k8s.yaml.j2",
            policy=_policy(POSTGRES, project, namespace, connections),
            **common,
        )
    return files


def _policy(name: str, project: str, namespace: str, connections: list[Connection]) -> str:
    """The NetworkPolicy of data-service workload ``name`` (a store's or PostgreSQL)."""
    labels = {"app.kubernetes.io/name": name, "app.kubernetes.io/part-of": project}
    return _yaml(workload_policy(name, namespace, labels, connections))
