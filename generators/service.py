"""Generator of the cloud data-acquisition services: one web service per ``store``.

A store becomes ``services/<Store>/``: a FastAPI + SQLAlchemy 2 application (uvicorn
serves it) with its first-order table, one typed table per refinement, the compiled
transforms and a transformer, plus README, pyproject.toml and requirements.txt. The
templates under ``templates/service`` hold the code; this module only builds their
context from the resolved model, passing every model name through validation first.
"""

from __future__ import annotations

import re
from functools import cache
from typing import Any

from jinja2 import Environment, PackageLoader, StrictUndefined

from spl.diagnostics import Diagnostic, ModelError, location_of
from spl.dsl.transform_types import check_system
from spl.generators.expressions import (
    IDENTIFIER,
    function_name,
    neighbours_used,
    transforms_module,
)
from spl.resolver.product import ResolvedProduct

PYTHON_TYPES = {"double": "float", "int": "int", "string": "str", "bool": "bool"}
COLUMN_TYPES = {"double": "Double()", "int": "BigInteger()", "string": "Text()",
                "bool": "Boolean()"}
DEFAULT_PERIOD = 5.0
DATABASE_ATTRIBUTE = "database"  # a selected feature's attribute: "sqlite" | "postgresql"
POSTGRES_DEFAULT_URL = "postgresql://spl@localhost:5432/spl"

PACKAGE_FILES = ("__init__.py", "__main__.py", "settings.py", "database.py", "model.py",
                 "transformer.py", "ingest.py", "access.py", "app.py")
TOP_FILES = ("README.md", "pyproject.toml", "requirements.txt")


def snake_case(name: str) -> str:
    """``PositionStore`` -> ``position_store``; ``EV3Writer`` -> ``ev3_writer``."""
    if not IDENTIFIER.match(name):
        raise ValueError(f"not an identifier: {name!r}")
    words = re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", name)
    words = re.sub(r"([A-Z]+)([A-Z][a-z])", r"\1_\2", words)
    return re.sub(r"_+", "_", words).strip("_").lower() or "x"


def dns_name(name: str) -> str:
    """A Kubernetes/compose-safe name (RFC 1123 label) for a validated identifier."""
    return snake_case(name).replace("_", "-").strip("-")[:63] or "x"


@cache
def environment() -> Environment:
    env = Environment(
        loader=PackageLoader("spl.generators", "templates"),
        undefined=StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,  # Python, YAML and Markdown: values are validated or repr()-ed
    )
    env.filters["pyrepr"] = repr
    return env


def render(template: str, **context: Any) -> bytes:
    return environment().get_template(template).render(**context).encode("utf-8")


def cloud_stores(system: Any) -> list[Any]:
    return [
        store
        for container in system.containers
        if container.eClass.name == "CloudContainer"
        for store in container.stores
    ]


def _check_names(system: Any) -> None:
    """Every name that reaches generated code must be an identifier (hostile input)."""
    problems = []

    def need(element: Any, name: Any, what: str) -> None:
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


def database_kind(product: ResolvedProduct) -> str:
    """``sqlite`` or ``postgresql``: the value of a selected feature's ``database`` attribute.

    The data-acquisition product line puts ``attribute database`` on its storage
    alternatives, so the feature model, not this generator, decides.
    """
    selected = set(product.features)
    for key, value in sorted(product.attributes.items()):
        feature, _, attribute = key.rpartition(".")
        if attribute == DATABASE_ATTRIBUTE and feature in selected and value in (
            "sqlite", "postgresql"
        ):
            return value
    return "sqlite"


def store_context(store: Any, product: ResolvedProduct) -> dict[str, Any]:
    """The names one store's service, clients and deployment files agree on."""
    slug = snake_case(store.name)
    upper = slug.upper()
    default_url = (
        POSTGRES_DEFAULT_URL
        if database_kind(product) == "postgresql"
        else f"sqlite:///./{slug}.db"
    )
    return {
        "name": store.name,
        "name_repr": repr(store.name),
        "slug": slug,
        "dns": dns_name(store.name),
        "package": f"{slug}_service",
        "distribution": f"{slug.replace('_', '-')}-service",
        "prefix": f"/{store.name}",
        "token_env": f"{upper}_TOKEN",
        "protect_reads_env": f"{upper}_PROTECT_READS",
        "period_env": f"{upper}_TRANSFORM_PERIOD",
        "default_database_url": default_url,
        "raw_table": f"{slug}_raw",
        "raw_table_repr": repr(f"{slug}_raw"),
        "watermark_table_repr": repr(f"{slug}_watermarks"),
        "error_table": f"{slug}_errors",
        "error_table_repr": repr(f"{slug}_errors"),
    }


def _fields(data_type: Any) -> list[dict[str, str]]:
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


def _refinement_context(store: Any, refinement: Any) -> dict[str, Any]:
    neighbours = neighbours_used(refinement.transform)
    slug = snake_case(store.name)
    output = refinement.output
    return {
        "name": output.name,
        "transform": refinement.transform.name,
        "function": function_name(refinement.transform.name),
        "table_var": f"table_{snake_case(output.name)}",
        "table_name": f"{slug}_{snake_case(output.name)}",
        "fields": _fields(output),
        "period": float(refinement.period) if refinement.period else DEFAULT_PERIOD,
        "uses_prev": "prev" in neighbours,
        "uses_next": "next" in neighbours,
    }


def generate_store(store: Any, product: ResolvedProduct) -> dict[str, bytes]:
    context = {
        "product": product.name,
        "store": store_context(store, product),
        "raw": {"name": store.raw.name, "name_repr": repr(store.raw.name),
                "class_name": f"{store.raw.name}Record", "fields": _fields(store.raw)},
        "refinements": [_refinement_context(store, r) for r in store.refinements],
    }
    root = f"services/{store.name}"
    package = f"{root}/{context['store']['package']}"
    files = {f"{root}/{name}": render(f"service/{name}.j2", **context) for name in TOP_FILES}
    for name in PACKAGE_FILES:
        files[f"{package}/{name}"] = render(f"service/package/{name}.j2", **context)
    transforms = {id(r.transform): r.transform for r in store.refinements}
    files[f"{package}/transforms.py"] = transforms_module(transforms.values()).encode("utf-8")
    return files


def generate(product: ResolvedProduct) -> dict[str, bytes]:
    """``services/<Store>/...`` for every store of a cloud container of the product."""
    system = product.system
    _check_names(system)
    problems = [d for d in check_system(system) if d.severity == "error"]
    if problems:
        raise ModelError(problems)
    files: dict[str, bytes] = {}
    for store in cloud_stores(system):
        files.update(generate_store(store, product))
    return files
