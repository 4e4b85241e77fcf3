"""Generator of the cloud-side deployment files of the data-acquisition services.

``deploy/`` gets one Dockerfile per service, a docker-compose.yml running every
service (plus PostgreSQL when the product stores in PostgreSQL), and Kubernetes
manifests: a Deployment and Service per store, and PostgreSQL as a StatefulSet.
Secrets are only ever named: compose reads them from the environment, Kubernetes
from a Secret created out of band.
"""

from __future__ import annotations

from typing import TypedDict

from spl.generators.bundle_paths import BundleFiles
from spl.generators.jinja_templates import render
from spl.generators.store_contract import StoreContext, store_context
from spl.resolver.generated_names import dns_name
from spl.resolver.product import ResolvedProduct
from spl.resolver.stores import cloud_stores, database_kind

SERVICE_PORT = 8000
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


def generate(product: ResolvedProduct) -> dict[str, bytes]:
    stores = cloud_stores(product.system)
    if not stores:
        return {}
    project = _project(product)
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
            **common,
        )
    if postgres:
        files["deploy/kubernetes/postgres.yaml"] = render("deploy/postgres.k8s.yaml.j2", **common)
    return files
