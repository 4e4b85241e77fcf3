"""The data-acquisition part of a resolved product: the stores its cloud keeps, the
database it stores them in, and whether they can be generated.

The service, client and deployment generators all start from these facts; they are
facts about the product (its architecture and its feature selection), not about any
generated file, so they are decided here once.
"""

from __future__ import annotations

from typing import Any

from spl.diagnostics import Diagnostic
from spl.dsl.transform_types import check_system
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
