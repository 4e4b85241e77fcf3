"""The application of a data-acquisition service (docs/services.md): a Linked Robotic
Thing after "Requirements and Specifications for Robots, Linked Data and all the REST".
The routes and their answers are the same in every service; what a product decides
(its store, record types, refinements, tables, Turtle, settings, token, database and
transformer) comes in as a ``StoreService``, which the generated ``app.py`` fills.

Robotic Thing (R0.1-R0.17): GET on the root, 201 + Location on creation, ETag on every
representation (and HEAD), OPTIONS with Allow everywhere, Link rel="related" from a
resource to its sub-resources, 400/401/404/406/413 with a JSON reason, and
subscriptions to the collections (reads.py, subscriptions.py, hub.py). Linked
(R1.1-R1.12): Turtle unless the Accept header prefers JSON, and the store's
subscriptions, properties, actions and blueprint (described.py). The OpenAPI document
lists every answer of every operation (contract.py).
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass
from typing import Any

from fastapi import Depends, FastAPI, Request
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import Response
from sqlalchemy import ColumnElement, Engine, Table, select

from . import contract, described, ingest, reads
from .access import BodyLimit, Guard, WriteRoute
from .answers import Answers, related
from .database import WriteTurns
from .hub import Hub
from .linked import StoreDocuments
from .records import FieldSpec, RecordModel, Refinement
from .routes import READ, Routes
from .settings import Settings

Worker = tuple[threading.Thread, threading.Event]


@dataclass(frozen=True)
class StoreService:
    """What one product's service is made of, as its generated modules define it."""

    store: str  # the store's name; its resources are under prefix ("/" + store)
    prefix: str
    raw_type: str
    raw_fields: tuple[FieldSpec, ...]
    refinements: tuple[Refinement, ...]
    raw_records: Table
    raw_key_where: ColumnElement[bool]  # the records an idempotency key names
    transform_errors: Table
    callback_subscriptions: Table
    raw_record_in: type[RecordModel]  # the body of a post, and of a batch
    raw_batch_in: type[RecordModel]
    linked: StoreDocuments  # the Turtle of the store's resources (linked.py)
    settings: Settings
    token_env: str  # the variable of the write token, named when it is missing
    guard: Guard
    write_route: type[WriteRoute]
    create_engine: Callable[[], Engine]
    write_turns: WriteTurns  # the process's turns to write, shared with its transformer
    start_transformer: Callable[[Engine, Callable[[], None]], Worker]
    log: logging.Logger


def raw_rows(records: list[Any], received: float) -> list[dict[str, Any]]:
    """The rows of posted records (``RawRecordIn``), all ``received`` at one time."""
    return [
        {
            "robot": r.robot,
            "source_ts": r.timestamp,
            "received_ts": received,
            "document": r.data.model_dump(by_alias=True),
            "key": r.key,
        }
        for r in records
    ]


def type_document(fields: tuple[FieldSpec, ...]) -> list[dict[str, str]]:
    """The fields of a data type as the store's document lists them."""
    return [{"name": f.name, "type": f.type} for f in fields]


def _database_answers(engine: Engine) -> None:
    """A round trip to the database, which fails (500) when it is gone."""
    with engine.connect() as conn:
        conn.execute(select(1))


WRITES = (201, 400, 401, 406, 413, 500)


def create_app(service: StoreService) -> FastAPI:
    """The application of ``service``: every route, in the order the router tries them."""
    settings, prefix, linked = service.settings, service.prefix, service.linked
    answers = Answers(linked.negotiate)
    collections = reads.collections(service)

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        if not settings.token:
            raise RuntimeError(f"set {service.token_env} to the bearer token writers must present")
        app.state.engine = service.create_engine()
        app.state.hub = Hub(
            app.state.engine,
            collections,
            service.callback_subscriptions,
            prefix,
            service.write_turns,
            settings.callback_hosts,
        ).start()
        app.state.writer = ingest.RecordWriter(
            app.state.engine,
            service.write_turns,
            service.raw_records,
            service.raw_key_where,
            app.state.hub.wake,
        ).start()
        worker = None
        if settings.transformer == "embedded":
            worker = service.start_transformer(app.state.engine, app.state.hub.wake)
        yield
        await app.state.hub.close()
        if worker is not None:
            thread, stop = worker
            stop.set()
            thread.join(timeout=10)
        app.state.writer.close()
        app.state.engine.dispose()

    app = FastAPI(
        title=f"{service.store} data-acquisition service",
        description=contract.description(service.raw_type),
        version="1.0.0",
        lifespan=lifespan,
    )
    app.openapi = lambda: contract.openapi(  # type: ignore[method-assign]
        app,
        contract.schemas(service.raw_fields, service.refinements),
        service.token_env,
        settings.protect_reads,
    )
    app.add_middleware(BodyLimit, limit=settings.max_body)  # 413: access.py
    routes = Routes(app)
    routes.answer_errors(service.log)

    async def post_record(request: Request, record: Any) -> Response:
        media = answers.media_of(request)  # before storing: an unacceptable answer stores nothing
        (record_id,) = await request.app.state.writer.store(raw_rows([record], time.time()))
        location = f"{prefix}/records/{record_id}"
        return answers.represent(
            request,
            {"id": record_id, "href": location},
            lambda links: linked.created(links, [location], batch=False),
            status=201,
            headers={"Location": location},
            media=media,
        )

    async def post_batch(request: Request, batch: Any) -> Response:
        media = answers.media_of(request)
        ids = await request.app.state.writer.store(raw_rows(batch.records, time.time()))
        hrefs = [f"{prefix}/records/{i}" for i in ids]
        return answers.represent(
            request,
            {"ids": ids, "hrefs": hrefs},
            lambda links: linked.created(links, hrefs, batch=True),
            status=201,
            headers={"Location": hrefs[0]},
            media=media,
        )

    # the bodies are the product's record types: FastAPI reads them from the signature
    post_record.__annotations__["record"] = service.raw_record_in
    post_batch.__annotations__["batch"] = service.raw_batch_in
    # The writes come first: the router tries routes in order, and posts are the traffic.
    for path, endpoint, name, body, summary in [
        (prefix + "/records", post_record, "record", "Created", "Store one raw record"),
        (
            prefix + "/records/batch",
            post_batch,
            "batch",
            "BatchCreated",
            "Store up to MAX_BATCH (default 1000) raw records in one transaction",
        ),
    ]:
        app.router.add_api_route(
            path,
            endpoint,
            methods=["POST"],
            status_code=201,
            summary=summary,
            route_class_override=service.write_route,
            name=f"post_{name}",
            operation_id=f"post_{name}",
            openapi_extra={contract.STATUSES: WRITES, contract.TOKEN: True, contract.BODY: body},
        )

    async def root(request: Request) -> Response:
        """Always open: it only links to the store. Readiness probes use it, so it answers
        only after a round trip to the database (one that fails is a 500): a service whose
        database is gone takes no more traffic until it is back."""
        await run_in_threadpool(_database_answers, request.app.state.engine)
        return answers.represent(
            request, {"stores": [prefix]}, linked.root, headers={"Link": related(prefix)}
        )

    routes.resource(
        "/", root, "root", (200, 304, 406, 500), "The service: links to its store", "Root"
    )
    routes.options("/", "root", READ)

    sub_resources = [
        f"{prefix}/{name}" for name in ("subscriptions", "blueprint", "properties", "actions")
    ]

    async def store(request: Request) -> Response:
        document = {
            "store": service.store,
            "raw": {
                "type": service.raw_type,
                "fields": type_document(service.raw_fields),
                "href": f"{prefix}/records",
            },
            "refined": [
                {
                    "type": r.name,
                    "fields": type_document(r.fields),
                    "period": r.period,
                    "href": f"{prefix}/{r.name}",
                }
                for r in service.refinements
            ],
            "errors": {"href": f"{prefix}/errors"},
            "subscriptions": {"href": f"{prefix}/subscriptions"},
            "blueprint": {"href": f"{prefix}/blueprint"},
            "properties": {"href": f"{prefix}/properties"},
            "actions": {"href": f"{prefix}/actions"},
        }
        return answers.represent(
            request,
            document,
            linked.store,
            headers={"Link": related(*linked.collections(), *sub_resources)},
        )

    reader = [Depends(service.guard.reader)]
    routes.resource(
        prefix,
        store,
        "store",
        reads.read_answers(settings),
        "The store: its collections and sub-resources",
        "Store",
        dependencies=reader,
    )
    routes.options(prefix, "store", READ)
    routes.options(prefix + "/records/batch", "batch", "POST, OPTIONS")
    reads.add_routes(service, routes, answers, collections)
    described.add_routes(service, routes, answers)
    return app
