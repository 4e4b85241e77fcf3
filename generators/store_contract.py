"""The names one store's service, its robot-side clients and its deployment agree on.

A store becomes a web service (``service``), is written to and read from by generated
ROS 2 clients (``clients``) and is deployed with Docker Compose and Kubernetes
(``deploy``): the package, URL prefix, environment variables, tables and default
database URL must be the same in all of them, so they are derived here once.
"""

from __future__ import annotations

from typing import Any

from spl.resolver.product import ResolvedProduct
from spl.resolver.stores import database_kind, store_names, store_tables, table_indexes

POSTGRES_DEFAULT_URL = "postgresql://spl@localhost:5432/spl"


def store_context(store: Any, product: ResolvedProduct) -> dict[str, Any]:
    """The names one store's service, clients and deployment files agree on (unique
    across the product's stores: :func:`spl.resolver.stores.store_names`)."""
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
        "default_database_url": default_url,
        "raw_table": tables.raw,
        "raw_table_repr": repr(tables.raw),
        "raw_indexes": table_indexes(tables.raw),
        "watermark_table_repr": repr(tables.watermarks),
        "error_table": tables.errors,
        "error_table_repr": repr(tables.errors),
    }
