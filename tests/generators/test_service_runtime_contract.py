"""The runtime's OpenAPI contract and settings, imported directly (docs/services.md,
"OpenAPI" and "Settings"): each operation lists exactly the statuses its route names,
with the problem schema and the token where they apply; the store's own record types
become schemas; the settings come from the product's variables, secrets from files.
tests/live/test_service_openapi.py runs schemathesis against the same contract live."""

from __future__ import annotations

from pathlib import Path

import pytest
from fastapi import FastAPI
from sqlalchemy import Column, Integer, MetaData, Table

from spl.generators.service.runtime import contract
from spl.generators.service.runtime.records import FieldSpec, Refinement
from spl.generators.service.runtime.settings import EnvironmentNames, load

RAW = (FieldSpec("price", "double"), FieldSpec("label", "string"))
REFINED = Refinement(
    name="Cheap",
    table=Table("cheap", MetaData(), Column("id", Integer, primary_key=True)),
    fields=(FieldSpec("paid", "bool"), FieldSpec("count", "int")),
    transform=lambda current, prev, next_: current,
    period=5.0,
    uses_prev=False,
    uses_next=False,
)


def _app() -> FastAPI:
    app = FastAPI(title="Shop", description=contract.description("Sale"))

    async def read() -> None:
        return None

    routes = [
        (
            "/Shop/records",
            "GET",
            {contract.STATUSES: (200, 304, 401, 406), contract.BODY: "RawPage"},
        ),
        ("/Shop/records", "POST", {contract.STATUSES: (201, 400, 413), contract.TOKEN: True}),
        ("/Shop", "OPTIONS", {contract.STATUSES: (204,), contract.ALLOW: "GET, OPTIONS"}),
    ]
    for path, method, extra in routes:
        app.add_api_route(path, read, methods=[method], openapi_extra=extra)
    return app


@pytest.mark.parametrize("protect_reads", [False, True])
def test_each_operation_answers_exactly_its_statuses(protect_reads: bool) -> None:
    app = _app()
    schemas = contract.schemas(RAW, [REFINED])
    document = contract.openapi(app, schemas, "SHOP_STORE_TOKEN", protect_reads)
    assert contract.openapi(app, {}, "OTHER", False) is document  # made once
    read = document["paths"]["/Shop/records"]["get"]
    write = document["paths"]["/Shop/records"]["post"]
    options = document["paths"]["/Shop"]["options"]
    assert sorted(read["responses"]) == ["200", "304", "401", "406"]
    assert sorted(write["responses"]) == ["201", "400", "413"]
    assert read["responses"]["200"]["content"]["application/json"]["schema"] == {
        "$ref": "#/components/schemas/RawPage"
    }
    assert read["responses"]["406"]["content"]["application/json"]["schema"] == {
        "$ref": "#/components/schemas/Problem"
    }
    assert options["responses"]["204"]["headers"]["Allow"]["description"] == (
        "the methods: GET, OPTIONS"
    )
    assert write["security"] == [{"bearer": []}]
    assert ("security" in read) is protect_reads
    assert not any(contract.STATUSES in op or contract.TOKEN in op for op in (read, write))
    found = document["components"]["schemas"]
    assert "HTTPValidationError" not in found and "Problem" in found
    assert "SHOP_STORE_TOKEN" in document["components"]["securitySchemes"]["bearer"]["description"]
    assert "First-order store of Sale records" in document["info"]["description"]


def test_the_store_s_record_types_are_schemas() -> None:
    found = contract.schemas(RAW, [REFINED])
    assert found["RawRecord"]["properties"]["data"]["properties"] == {
        "price": {"type": "number"},
        "label": {"type": "string"},
    }
    refined = found["Refined_Cheap"]["properties"]
    assert (refined["paid"], refined["count"]) == ({"type": "boolean"}, {"type": "integer"})
    assert found["Page_Cheap"]["properties"]["items"]["items"] == {
        "$ref": "#/components/schemas/Refined_Cheap"
    }


NAMES = EnvironmentNames(
    token="SHOP_STORE_TOKEN",
    protect_reads="SHOP_STORE_PROTECT_READS",
    period="SHOP_STORE_PERIOD",
    tls_cert="SHOP_STORE_TLS_CERT",
    tls_key="SHOP_STORE_TLS_KEY",
    callback_hosts="SHOP_STORE_CALLBACK_HOSTS",
    default_database_url="sqlite:///shop.db",
)


def test_settings_come_from_the_product_s_variables(tmp_path: Path) -> None:
    default = load(NAMES, {})
    assert (default.database_url, default.token, default.protect_reads) == (
        "sqlite:///shop.db", "", False,
    )  # fmt: skip
    assert (default.max_batch, default.max_body, default.period(2.0)) == (1000, 16384000, 2.0)
    secret = tmp_path / "token"
    secret.write_text("s3cret\n", encoding="utf-8")
    environ = {
        "SHOP_STORE_TOKEN_FILE": str(secret),
        "SHOP_STORE_TOKEN": "ignored: the file wins",
        "SHOP_STORE_PROTECT_READS": " Yes ",
        "SHOP_STORE_PERIOD": "0.5",
        "SHOP_STORE_CALLBACK_HOSTS": "hooks.internal:8443",
        "MAX_BATCH": "10",
        "DATABASE_URL": "postgresql://db/shop",
    }
    found = load(NAMES, environ)
    assert (found.token, found.protect_reads, found.period(2.0)) == ("s3cret", True, 0.5)
    assert found.callback_hosts.hosts == frozenset({("hooks.internal", 8443)})
    assert (found.max_body, found.database_url) == (2**20, "postgresql://db/shop")


def test_an_unreadable_secret_file_stops_the_service_naming_it(tmp_path: Path) -> None:
    missing = tmp_path / "absent"
    with pytest.raises(SystemExit, match=f"SHOP_STORE_TOKEN_FILE='{missing}': cannot read"):
        load(NAMES, {"SHOP_STORE_TOKEN_FILE": str(missing)})
