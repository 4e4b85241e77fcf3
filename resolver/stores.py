"""The data-acquisition part of a resolved product: the stores its cloud keeps, the
database it stores them in, and whether they can be generated.

The service, client and deployment generators all start from these facts; they are
facts about the product (its architecture and its feature selection), not about any
generated file, so they are decided here once.
"""

from __future__ import annotations

from typing import Any, NamedTuple

from spl.diagnostics import Diagnostic
from spl.dsl.transform_types import check_system
from spl.resolver.generated_names import dns_name, lower_identifier, snake_case, unique_names
from spl.resolver.product import ResolvedProduct

DATABASE_ATTRIBUTE = "database"  # a selected feature's attribute, one of DATABASES
DATABASES = ("sqlite", "postgresql")


def cloud_stores(system: Any) -> list[Any]:
    """The stores of the cloud containers, in model order."""
    return [
        store
        for container in system.containers
        if container.eClass.name == "CloudContainer"
        for store in container.stores
    ]


class StoreNames(NamedTuple):
    """What one store's generated artefacts are named after (see :func:`store_names`)."""

    key: str  # folder under services/ and deploy/, URL prefix: the store's name, or C_Store
    slug: str  # Python package, tables, environment variables, SQLite file: position_store
    dns: str  # Docker Compose service, Kubernetes objects: position-store


# the deployment's own PostgreSQL (compose service, Kubernetes StatefulSet and Service)
RESERVED_STORE_FORMS = frozenset({"dns:postgres", "dir:postgres"})


def store_tables(slug: str, store: Any) -> list[str]:
    """The tables a store keeps in the product's one database: raw records, transformer
    watermarks, failed records and one per refined type."""
    refined = [snake_case(r.output.name) for r in store.refinements if r.output is not None]
    return [f"{slug}_raw", f"{slug}_watermarks", f"{slug}_errors"] + [
        f"{slug}_{name}" for name in refined
    ]


def _names(key: str) -> StoreNames:
    slug = lower_identifier(key, "store")
    return StoreNames(key, slug, dns_name(slug))


def _forms(store: Any, key: str) -> set[str]:
    names = _names(key)
    tables = {f"table:{table}" for table in store_tables(names.slug, store)}
    return {f"dir:{key.lower()}", f"py:{names.slug}", f"dns:{names.dns}"} | tables


def store_names(system: Any) -> dict[int, StoreNames]:
    """The names of every cloud store (by ``id``), unique across the product: a store
    is named after itself, or after its container and itself where two stores of the
    product would otherwise share a folder, package, table or Kubernetes name (two
    containers each holding a ``PositionStore``)."""
    stores = [
        (store, container.name, store.name)
        for container in system.containers
        if container.eClass.name == "CloudContainer"
        for store in container.stores
    ]
    keys = unique_names(stores, _forms, RESERVED_STORE_FORMS)
    return {id(store): _names(key) for (store, _, _), key in zip(stores, keys, strict=True)}


def database_kind(product: ResolvedProduct) -> str:
    """``sqlite`` or ``postgresql``: the value of a selected feature's ``database`` attribute.

    The data-acquisition product line puts ``attribute database`` on its storage
    alternatives, so the feature model, not a generator, decides.
    """
    selected = set(product.features)
    for key, value in sorted(product.attributes.items()):
        feature, _, attribute = key.rpartition(".")
        if attribute == DATABASE_ATTRIBUTE and feature in selected and value in DATABASES:
            return value
    return "sqlite"


def store_errors(system: Any) -> list[Diagnostic]:
    """What keeps the stores of ``system`` from being generated: ill-typed transforms,
    reserved field names, refinements that do not fit their store. The .tsm parser
    reports them too; a generator checks again, as a rewritten or hand-built model
    reaches it without the parser."""
    return [d for d in check_system(system) if d.severity == "error"]
