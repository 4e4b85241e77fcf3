"""Generator of the cloud data-acquisition services: one web service per ``store``.

A store becomes ``services/<Store>/``: a FastAPI + SQLAlchemy 2 application (uvicorn
serves it) with its first-order table, one typed table per refinement, the compiled
transforms and a transformer, plus README, pyproject.toml and requirements.txt. What is
the same in every service is :mod:`spl.generators.service.runtime`, copied byte for byte
into the service's package as ``runtime/`` (docs/services.md, "The runtime package");
the templates under ``templates/service`` hold what the product decides, and this
module builds their context from the resolved model (the names the clients and the
deployment share are :mod:`spl.generators.store_contract`'s), passing every model name
through validation first.
"""

from __future__ import annotations

from importlib.resources import files as package_files
from typing import TYPE_CHECKING

from spl.core.diagnostics import Diagnostic, ModelError, location_of
from spl.generators.bundle.paths import BundleFiles
from spl.generators.jinja_templates import render
from spl.generators.service.expressions import function_name, neighbours_used, transforms_module
from spl.generators.store_contract import store_context
from spl.resolver.architecture.generated_names import IDENTIFIER, snake_case
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.stores import (
    cloud_stores,
    relation_name,
    store_errors,
    store_names,
    store_relations,
    store_tables,
    table_indexes,
)

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

# the types of a posted record's fields (model.py.j2 defines Int64 and StoredText: what the
# columns and PostgreSQL can hold, so a record that could never be stored is a 400)
PYTHON_TYPES = {"double": "float", "int": "Int64", "string": "StoredText", "bool": "bool"}
COLUMN_TYPES = {
    "double": "Double()",
    "int": "BigInteger()",
    "string": "Text()",
    "bool": "Boolean()",
}
DEFAULT_PERIOD = 5.0
# Sub-resources of a store next to its refined collections (``/<Store>/<RefinedType>``)
COLLECTION_NAMES = ("records", "errors", "subscriptions", "blueprint", "properties", "actions")

PACKAGE_FILES = (
    "__init__.py",
    "__main__.py",
    "settings.py",
    "database.py",
    "model.py",
    "transformer.py",
    "access.py",
    "linked.py",
    "app.py",
)
RUNTIME = "spl.generators.service.runtime"  # shipped as <package>/runtime/
TOP_FILES = ("README.md", "pyproject.toml", "requirements.txt")


def _check_names(system: tsm_types.System) -> None:
    """Every name that reaches generated code must be an identifier (hostile input)."""
    problems = []
    system_name = getattr(system, "name", None)  # None: a .tsm without a system line
    if system_name is not None and (
        not isinstance(system_name, str) or not IDENTIFIER.match(system_name)
    ):
        problems.append(Diagnostic(location_of(system), f"invalid system name {system_name!r}"))

    def need(element: tsm_types.Located, name: object, what: str) -> None:
        if not isinstance(name, str) or not IDENTIFIER.match(name):
            problems.append(Diagnostic(location_of(element), f"invalid {what} name {name!r}"))

    for store in cloud_stores(system):
        need(store, store.name, "store")
        for data_type in [store.raw] + [r.output for r in store.refinements]:
            if data_type is None:
                problems.append(Diagnostic(location_of(store), f"store {store.name}: no type"))
                continue
            need(data_type, data_type.name, "data type")
            for field in data_type.fields:
                need(field, field.name, "field")
    if problems:
        raise ModelError(problems)


def _service_errors(system: tsm_types.System) -> list[Diagnostic]:
    """Names the service itself takes: a refined collection named like one of the store's
    own sub-resources, a table or index of the service named like one the store uses."""
    problems = []
    names = store_names(system)
    for store in cloud_stores(system):
        slug = names[id(store)].slug
        for refinement in store.refinements:
            if refinement.output is not None and refinement.output.name in COLLECTION_NAMES:
                problems.append(
                    Diagnostic(
                        location_of(refinement) or location_of(store),
                        f"store {store.name}: refined type {refinement.output.name} would be "
                        f"served at /{store.name}/{refinement.output.name}, a resource of the "
                        "store itself; rename the refined type",
                    )
                )
        tables = store_tables(slug, store)
        taken = {name: element for name, element in store_relations(slug, store)}
        for own in (
            relation_name(f"{tables.raw}_robot_key"),
            relation_name(f"{slug}_subscriptions"),
        ):
            if own in taken:
                element = taken[own]
                problems.append(
                    Diagnostic(
                        location_of(element) or location_of(store),
                        f"store {store.name}: the database name {own} is the service's own; "
                        "rename the refined type",
                    )
                )
    return problems


def _fields(data_type: tsm_types.DataType) -> list[dict[str, str]]:
    return [
        {
            "name": f.name,
            "name_repr": repr(f.name),
            "attr": f"f{index}",
            "type": f.type.name,
            "pytype": PYTHON_TYPES[f.type.name],
            "column": COLUMN_TYPES[f.type.name],
        }
        for index, f in enumerate(data_type.fields)
    ]


def _refinement_context(
    slug: str, store: tsm_types.Store, refinement: tsm_types.Refinement
) -> dict[str, object]:
    neighbours = neighbours_used(refinement.transform)
    output = refinement.output
    table = store_tables(slug, store).refined[output.name]
    return {
        "name": output.name,
        "transform": refinement.transform.name,
        "function": function_name(refinement.transform.name),
        "table_var": f"table_{snake_case(output.name)}",
        "table_name": table,
        "indexes": table_indexes(table),
        "fields": _fields(output),
        "period": float(refinement.period) if refinement.period else DEFAULT_PERIOD,
        "uses_prev": "prev" in neighbours,
        "uses_next": "next" in neighbours,
    }


def runtime_files() -> dict[str, bytes]:
    """The runtime's modules by file name, as they are in spl (copied, not rendered)."""
    found = {}
    for entry in package_files(RUNTIME).iterdir():
        if entry.name.endswith(".py") and entry.is_file():
            found[entry.name] = entry.read_bytes()
    return dict(sorted(found.items()))


def generate_store(store: tsm_types.Store, product: ResolvedProduct) -> dict[str, bytes]:
    names = store_context(store, product)
    context = {
        "product": product.name,
        "system_repr": repr(product.system.name),
        "store": names,
        "raw": {
            "name": store.raw.name,
            "name_repr": repr(store.raw.name),
            "class_name": f"{store.raw.name}Record",
            "fields": _fields(store.raw),
        },
        "refinements": [_refinement_context(names["slug"], store, r) for r in store.refinements],
    }
    root = f"services/{names['name']}"
    package = f"{root}/{names['package']}"  # the context's store is these names
    files = {f"{root}/{name}": render(f"service/{name}.j2", **context) for name in TOP_FILES}
    for name in PACKAGE_FILES:
        files[f"{package}/{name}"] = render(f"service/package/{name}.j2", **context)
    for name, data in runtime_files().items():
        files[f"{package}/runtime/{name}"] = data
    transforms = {id(r.transform): r.transform for r in store.refinements}
    files[f"{package}/transforms.py"] = transforms_module(transforms.values()).encode("utf-8")
    return files


def generate(product: ResolvedProduct) -> dict[str, bytes]:
    """``services/<Store>/...`` for every store of a cloud container of the product
    (``services/<Container>_<Store>/`` where two containers hold stores of one name)."""
    system = product.system
    _check_names(system)
    problems = store_errors(system) or _service_errors(system)
    if problems:
        raise ModelError(problems)
    files = BundleFiles()
    for store in cloud_stores(system):
        files.update(generate_store(store, product))
    return files
