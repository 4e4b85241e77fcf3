"""The data-acquisition part of a resolved product: the stores its cloud keeps, the
database it stores them in, and whether they can be generated.

The service, client and deployment generators all start from these facts; they are
facts about the product (its architecture and its feature selection), not about any
generated file, so they are decided here once.
"""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING, NamedTuple, cast

from spl.core.diagnostics import Diagnostic, location_of
from spl.dsl.tsm.transform_types import check_system
from spl.resolver.architecture.generated_names import (
    ZENOH_ROUTER,
    dns_name,
    kubernetes_label,
    lower_identifier,
    snake_case,
    unique_names,
)
from spl.resolver.architecture.placement import Placement
from spl.resolver.architecture.product import ResolvedProduct

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

    # what a table or an index of a store comes from
    Source = tsm_types.Store | tsm_types.Refinement

DATABASE_ATTRIBUTE = "database"  # a selected feature's attribute, one of DATABASES
DATABASES = ("sqlite", "postgresql")


def cloud_stores(system: tsm_types.System) -> list[tsm_types.Store]:
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
# and the Zenoh router's Kubernetes objects
RESERVED_STORE_FORMS = frozenset({"dns:postgres", "dir:postgres", f"dns:{ZENOH_ROUTER}"})


POSTGRES_NAME_LIMIT = 63  # bytes PostgreSQL keeps of a table or index name


def relation_name(name: str) -> str:
    """A table or index name as the database keeps it: as is up to 63 characters, else
    its start and a digest of the whole (PostgreSQL would cut it silently, and two long
    names that start alike would become one)."""
    if len(name) <= POSTGRES_NAME_LIMIT:
        return name
    digest = hashlib.sha256(name.encode("utf-8")).hexdigest()[:8]
    return f"{name[: POSTGRES_NAME_LIMIT - 9]}_{digest}"


class StoreTables(NamedTuple):
    """The tables one store keeps in the product's one database."""

    raw: str  # records as they arrive
    watermarks: str  # each transformer's progress
    errors: str  # records a transform failed on
    refined: dict[str, str]  # refined data type name -> its table


def store_tables(slug: str, store: tsm_types.Store) -> StoreTables:
    refined = {
        r.output.name: relation_name(f"{slug}_{snake_case(r.output.name)}")
        for r in store.refinements
        if r.output is not None
    }
    return StoreTables(
        relation_name(f"{slug}_raw"),
        relation_name(f"{slug}_watermarks"),
        relation_name(f"{slug}_errors"),
        refined,
    )


def table_indexes(table: str) -> tuple[str, str]:
    """The indexes of a raw or refined table: by time, and by robot and time."""
    return relation_name(f"{table}_time"), relation_name(f"{table}_robot_time")


def store_relations(slug: str, store: tsm_types.Store) -> list[tuple[str, Source]]:
    """Every table and index name of a store, with the element it comes from (the
    store, or the refinement of a refined table), in order."""
    tables = store_tables(slug, store)
    found: list[tuple[str, Source]] = [
        (tables.raw, store),
        (tables.watermarks, store),
        (tables.errors, store),
    ]
    found += [(index, store) for index in table_indexes(tables.raw)]
    for refinement in store.refinements:
        if refinement.output is not None:
            table = tables.refined[refinement.output.name]
            found += [(name, refinement) for name in (table, *table_indexes(table))]
    return found


def _names(key: str) -> StoreNames:
    slug = lower_identifier(key, "store")
    return StoreNames(key, slug, dns_name(slug))


def _forms(store: tsm_types.Store, key: str) -> set[str]:
    names = _names(key)
    relations = {f"table:{name}" for name, _ in store_relations(names.slug, store)}
    return {f"dir:{key.lower()}", f"py:{names.slug}", f"dns:{names.dns}"} | relations


def store_names(system: tsm_types.System) -> dict[int, StoreNames]:
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
    # the cloud instances' Deployments and Services (kubernetes/) may share a namespace
    # with the stores' (deploy/kubernetes/): a store does not take an instance's name
    instances = Placement(system, []).cloud_instances() if stores else []
    taken = {f"dns:{kubernetes_label(instance.place.tag)}" for instance in instances}
    keys = unique_names(stores, _forms, RESERVED_STORE_FORMS | taken)
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


def store_errors(system: tsm_types.System) -> list[Diagnostic]:
    """What keeps the stores of ``system`` from being generated: ill-typed transforms,
    reserved field names, refinements that do not fit their store, a refined type whose
    table or index would take a name the store already uses (``Raw``, ``Errors``...).
    The .tsm parser reports most of them too; a generator checks again, as a rewritten
    or hand-built model reaches it without the parser."""
    problems = [d for d in check_system(system) if d.severity == "error"]
    names = store_names(system)
    for store in cloud_stores(system):
        seen: dict[str, Source] = {}
        refused: set[int] = set()  # one error per refined type, at its first clash
        for name, element in store_relations(names[id(store)].slug, store):
            first = seen.setdefault(name, element)
            if first is not element and id(element) not in refused:
                refused.add(id(element))
                what = (
                    f"refined type {cast('tsm_types.Refinement', element).output.name}"
                    if element is not store
                    else "it"
                )
                problems.append(
                    Diagnostic(
                        location_of(element) or location_of(store),
                        f"store {store.name}: {what} would be kept under the database name "
                        f"{name}, which the store already uses; rename the refined type",
                    )
                )
    return problems
