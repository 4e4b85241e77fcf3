"""The names one store's service, its robot-side clients and its deployment agree on.

A store becomes a web service (``service``), is written to and read from by generated
ROS 2 clients (``clients``) and is deployed with Docker Compose and Kubernetes
(``deploy``): the package, URL prefix, environment variables, tables and default
database URL must be the same in all of them, so they are derived here once.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, TypedDict

from spl.resolver.architecture.generated_names import snake_case
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.stores import (
    database_kind,
    relation_name,
    store_names,
    store_tables,
    table_indexes,
)

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

POSTGRES_DEFAULT_URL = "postgresql://spl@localhost:5432/spl"


class StoreContext(TypedDict):
    """The names of :func:`store_context` (the templates read them by these keys)."""

    name: str
    name_repr: str
    slug: str
    dns: str
    package: str
    distribution: str
    prefix: str
    token_env: str
    protect_reads_env: str
    period_env: str
    tls_cert_env: str
    tls_key_env: str
    callback_hosts_env: str
    default_database_url: str
    raw_table: str
    raw_table_repr: str
    raw_indexes: tuple[str, str]
    watermark_table_repr: str
    error_table: str
    error_table_repr: str
    key_index: str
    subscription_table: str


class ClientSettings(TypedDict):
    """What :func:`client_settings` gives a writer's or reader's packages and launch."""

    url_argument: str
    default_url: str
    robot_id: str
    period: float


def store_context(store: tsm_types.Store, product: ResolvedProduct) -> StoreContext:
    """The names one store's service, clients and deployment files agree on (unique
    across the product's stores: :func:`spl.resolver.architecture.stores.store_names`)."""
    key, slug, dns = store_names(product.system)[id(store)]
    tables = store_tables(slug, store)
    upper = slug.upper()
    default_url = (
        POSTGRES_DEFAULT_URL if database_kind(product) == "postgresql" else f"sqlite:///./{slug}.db"
    )
    return {
        "name": key,
        "name_repr": repr(key),
        "slug": slug,
        "dns": dns,
        "package": f"{slug}_service",
        "distribution": f"{slug.replace('_', '-')}-service",
        "prefix": f"/{key}",
        "token_env": f"{upper}_TOKEN",
        "protect_reads_env": f"{upper}_PROTECT_READS",
        "period_env": f"{upper}_TRANSFORM_PERIOD",
        # HTTPS: the certificate chain and private key files (PEM) uvicorn serves with
        "tls_cert_env": f"{upper}_TLS_CERT",
        "tls_key_env": f"{upper}_TLS_KEY",
        # the hosts callback subscriptions may post to (comma-separated; unset: any)
        "callback_hosts_env": f"{upper}_CALLBACK_HOSTS",
        "default_database_url": default_url,
        "raw_table": tables.raw,
        "raw_table_repr": repr(tables.raw),
        "raw_indexes": table_indexes(tables.raw),
        "watermark_table_repr": repr(tables.watermarks),
        "error_table": tables.errors,
        "error_table_repr": repr(tables.errors),
        # the service's own relations beyond spl.resolver.architecture.stores.store_relations
        "key_index": relation_name(f"{tables.raw}_robot_key"),
        "subscription_table": relation_name(f"{slug}_subscriptions"),
    }


DEFAULT_STORE_URL = "http://localhost:8000"
ROBOT_ID = re.compile(r"[A-Za-z0-9_.\-]{1,64}\Z")


def client_settings(
    container: tsm_types.Container,
    node: tsm_types.Writer | tsm_types.Reader,
    product: ResolvedProduct,
) -> ClientSettings:
    """What a writer's or reader's packages and the launch files starting it agree on:
    the launch argument naming its store's URL, the default URL, the robot id a writer
    stamps its records with, and a reader's poll period."""
    slug = store_context(node.store, product)["slug"]
    robot_id = (container.endpoint.robotId if container.endpoint is not None else None) or ""
    return {
        "url_argument": f"{slug}_url",
        "default_url": DEFAULT_STORE_URL,
        "robot_id": robot_id if ROBOT_ID.match(robot_id) else snake_case(container.name),
        "period": float(period) if (period := getattr(node, "period", None)) else 1.0,
    }
