"""The runtime's application of a service, imported directly (docs/services.md, "The
runtime package"): its answers (the ETag, the problem shape, the related links), the
routes it adds (one per method, HEAD without the answers that create or switch
protocols, OPTIONS declaring its path's parameters, Allow on a 405), the answers a read
documents, and the JSON of records, properties and actions. The live tests run the
whole application inside generated services (tests/live/test_service_*.py)."""

from __future__ import annotations

import asyncio
import logging
import typing
from types import SimpleNamespace

import httpx
import pytest
from fastapi import FastAPI, HTTPException
from fastapi.responses import Response
from pydantic import Field
from sqlalchemy import Column, Integer, MetaData, Table

from spl.generators.service.runtime import contract
from spl.generators.service.runtime.answers import etag, problem, related
from spl.generators.service.runtime.described import action_document, choices, property_document
from spl.generators.service.runtime.reads import (
    after_id,
    collection_answers,
    raw_document,
    read_answers,
    refined_document,
)
from spl.generators.service.runtime.records import FieldSpec, RecordModel, Refinement
from spl.generators.service.runtime.routes import (
    ID_MAX,
    Routes,
    head_answers,
    path_parameters,
)
from spl.generators.service.runtime.service import raw_rows
from spl.generators.service.runtime.settings import EnvironmentNames, load

NAMES = EnvironmentNames(
    token="SHOP_TOKEN",
    protect_reads="SHOP_PROTECT_READS",
    period="SHOP_PERIOD",
    tls_cert="SHOP_TLS_CERT",
    tls_key="SHOP_TLS_KEY",
    callback_hosts="SHOP_CALLBACK_HOSTS",
    default_database_url="sqlite:///shop.db",
)


def test_the_same_body_has_the_same_tag_and_another_body_another() -> None:
    tag = etag(b'{"id":1}')
    assert tag == etag(b'{"id":1}')
    assert tag != etag(b'{"id":2}')
    assert tag.startswith('"') and tag.endswith('"') and len(tag) == 34


def test_a_problem_names_its_status_and_reason_and_keeps_its_headers() -> None:
    answer = problem(401, "a bearer token is required", {"WWW-Authenticate": "Bearer"})
    assert answer.status_code == 401
    assert answer.body == b'{"status":401,"detail":"a bearer token is required"}'
    assert answer.headers["www-authenticate"] == "Bearer"


def test_related_links_every_sub_resource() -> None:
    assert related("/Shop", "/Shop/errors") == (
        '</Shop>; rel="related", </Shop/errors>; rel="related"'
    )


def test_a_head_creates_nothing_and_switches_no_protocol() -> None:
    assert head_answers((200, 101, 201, 304, 426, 401)) == (200, 304, 401)


def test_path_parameters_keep_their_convertor() -> None:
    assert path_parameters("/Shop/records/{record_id:int}") == [("record_id", "int")]
    assert path_parameters("/Shop/properties/{type_name}/{field}") == [
        ("type_name", ""),
        ("field", ""),
    ]


def _routes() -> Routes:
    routes = Routes(FastAPI())

    async def read(record_id: int) -> Response:
        if record_id == 0:
            raise HTTPException(404, "no record 0")
        return Response(str(record_id))

    async def cancel(record_id: int) -> Response:
        return Response(status_code=204)

    routes.resource("/Shop/{record_id:int}", read, "record", (200, 201, 404), "One record")
    routes.resource(
        "/Shop/{record_id:int}",
        cancel,
        "record",
        (204, 404),
        "Cancel",
        methods=("DELETE",),
        status_code=204,
    )
    routes.options("/Shop/{record_id:int}", "record", "GET, HEAD, DELETE, OPTIONS")
    routes.answer_errors(logging.getLogger("test"))
    return routes


def _ask(app: FastAPI, method: str, path: str) -> httpx.Response:
    async def ask() -> httpx.Response:
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://shop") as client:
            return await client.request(method, path)

    return asyncio.run(ask())


def test_each_method_is_its_own_operation_with_its_answers() -> None:
    operations = _routes().app.openapi()["paths"]["/Shop/{record_id}"]
    assert sorted(operations) == ["delete", "get", "head", "options"]
    assert operations["get"]["operationId"] == "get_record"
    assert operations["get"][contract.STATUSES] == [200, 201, 404]
    assert operations["head"][contract.STATUSES] == [200, 404]
    assert operations["options"][contract.STATUSES] == [204, 404]
    parameters = operations["options"]["parameters"]
    assert [(p["name"], p["schema"]["type"]) for p in parameters] == [("record_id", "integer")]


def test_options_allow_and_a_405_lists_every_method_of_the_path() -> None:
    routes = _routes()
    assert routes.allowed_methods("/Shop/7") == "GET, HEAD, DELETE, OPTIONS"
    assert routes.allowed_methods("/Shop/seven") == ""
    options = _ask(routes.app, "OPTIONS", "/Shop/7")
    assert (options.status_code, options.headers["allow"]) == (204, "GET, HEAD, DELETE, OPTIONS")
    refused = _ask(routes.app, "POST", "/Shop/7")
    assert refused.status_code == 405
    assert refused.headers["allow"] == "GET, HEAD, DELETE, OPTIONS"
    assert refused.json() == {"status": 405, "detail": "Method Not Allowed"}
    missing = _ask(routes.app, "GET", "/Shop/0")
    assert missing.json() == {"status": 404, "detail": "no record 0"}


def test_a_collection_documents_401_whether_reads_are_protected_or_not() -> None:
    open_ = load(NAMES, {})
    protected = load(NAMES, {"SHOP_PROTECT_READS": "1"})
    assert read_answers(open_) == (200, 304, 406, 500)
    assert read_answers(protected) == (200, 304, 406, 500, 401)
    assert 401 in collection_answers(open_)
    assert collection_answers(protected).count(401) == 1


def test_after_id_is_an_id_or_400() -> None:
    assert after_id(None) is None
    assert after_id("0") == 0
    assert after_id(str(ID_MAX)) == ID_MAX
    for wrong in (str(ID_MAX + 1), "-1", "1e3", ""):
        with pytest.raises(HTTPException) as refused:
            after_id(wrong)
        assert refused.value.status_code == 400


def test_records_as_json() -> None:
    raw = SimpleNamespace(
        id=3, robot="r1", source_ts=5.0, received_ts=6.0, document={"price": 1.5}, key=None
    )
    assert raw_document(raw) == {
        "id": 3,
        "robot": "r1",
        "timestamp": 5.0,
        "received": 6.0,
        "data": {"price": 1.5},
        "key": None,
    }
    cheap = Refinement(
        name="Cheap",
        table=Table("cheap", MetaData(), Column("id", Integer, primary_key=True)),
        fields=(FieldSpec("paid", "bool"),),
        transform=lambda current, prev, next_: current,
        period=5.0,
        uses_prev=False,
        uses_next=False,
    )
    refined = SimpleNamespace(
        id=1, raw_id=3, robot="r1", timestamp=5.0, _mapping={"paid": True, "other": 0}
    )
    assert refined_document(cheap, refined) == {
        "id": 1,
        "raw_id": 3,
        "robot": "r1",
        "timestamp": 5.0,
        "paid": True,
    }


def test_properties_and_actions_as_json() -> None:
    assert property_document(
        "urn:spl:model:Shop:",
        "/Shop/properties/Sale/price",
        "Sale",
        FieldSpec("price", "double"),
        "/Shop/records",
    ) == {
        "type": "Sale",
        "field": "price",
        "datatype": "double",
        "predicate": "urn:spl:model:Shop:Sale:price",
        "collection": "/Shop/records",
        "href": "/Shop/properties/Sale/price",
    }
    post = action_document("/Shop", "Sale", "post-record", ("POST", "/records", "Store"))
    assert post["target"] == "/Shop/records"
    assert post["consumes"] == "/Shop/blueprint#Sale"
    cancel = action_document("/Shop", "Sale", "cancel", ("DELETE", "/subscriptions/{id}", "x"))
    assert cancel["consumes"] is None and cancel["href"] == "/Shop/actions/cancel"


def test_choices_name_only_what_exists() -> None:
    assert typing.get_args(choices(["Sale", "Cheap"])) == ("Sale", "Cheap")


class Sale(RecordModel):
    """A raw record type whose field name is no Python name (the JSON key is the alias)."""

    price: float = Field(alias="price-eur")


class Posted(RecordModel):
    robot: str
    timestamp: float
    data: Sale
    key: str | None = None


def test_posted_records_become_rows_received_at_one_time() -> None:
    posted = [
        Posted.model_validate({"robot": "r1", "timestamp": 5, "data": {"price-eur": 2}}),
        Posted.model_validate(
            {"robot": "r2", "timestamp": 6, "key": "k", "data": {"price-eur": 3}}
        ),
    ]
    assert raw_rows(posted, 9.5) == [
        {
            "robot": "r1",
            "source_ts": 5.0,
            "received_ts": 9.5,
            "document": {"price-eur": 2.0},
            "key": None,
        },
        {
            "robot": "r2",
            "source_ts": 6.0,
            "received_ts": 9.5,
            "document": {"price-eur": 3.0},
            "key": "k",
        },
    ]
