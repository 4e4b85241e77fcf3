"""The collections of a service (raw records, each refined type, the transform errors):
pages by time range, robot and id, one record by id, and subscriptions to new records
by WebSocket (R0.12-R0.17) or by callback (docs/services.md, "Subscriptions").
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from fastapi import Depends, Header, HTTPException, Query, Request, WebSocket
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import Response
from sqlalchemy import Table, select

from . import callback_targets, subscriptions
from .answers import JSON, Answers, links_of, problem, related
from .records import Refinement
from .routes import COLLECTION, ID_MAX, MAX_PAGE, READ, Routes
from .settings import Settings
from .transform_errors import add_error_routes
from .turtle import Links

if TYPE_CHECKING:
    from .service import StoreService


def raw_document(row: Any) -> dict[str, Any]:
    """A raw record as JSON."""
    return {
        "id": row.id,
        "robot": row.robot,
        "timestamp": row.source_ts,
        "received": row.received_ts,
        "data": row.document,
        "key": row.key,
    }


def refined_document(refinement: Refinement, row: Any) -> dict[str, Any]:
    """A record of ``refinement`` as JSON: its ids, robot and time, then its fields."""
    document = {"id": row.id, "raw_id": row.raw_id, "robot": row.robot, "timestamp": row.timestamp}
    mapping = row._mapping
    for f in refinement.fields:
        document[f.name] = mapping[f.name]
    return document


def collections(service: StoreService) -> list[subscriptions.Collection]:
    """The collections one can subscribe to: the raw records first, then the refined."""
    linked, prefix = service.linked, service.prefix

    def refined(refinement: Refinement) -> subscriptions.Collection:
        return subscriptions.Collection(
            refinement.name,
            f"{prefix}/{refinement.name}",
            refinement.table,
            lambda row: JSON.encode(refined_document(refinement, row)),
            lambda links, row: linked.refined_record(links, refinement, row),
            linked.one,
        )

    raw = subscriptions.Collection(
        "records",
        f"{prefix}/records",
        service.raw_records,
        lambda row: JSON.encode(raw_document(row)),
        linked.raw_record,
        linked.one,
    )
    return [raw] + [refined(r) for r in service.refinements]


def read_answers(settings: Settings) -> tuple[int, ...]:
    """The answers of a read: 401 too when reads need the token."""
    return (200, 304, 406, 500) + ((401,) if settings.protect_reads else ())


def collection_answers(settings: Settings) -> tuple[int, ...]:
    """The answers of a collection, which also subscribes: a callback always needs the
    token, so 401 is among them whether reads are protected or not."""
    return (
        read_answers(settings) + (101, 201, 400, 426) + (() if settings.protect_reads else (401,))
    )


class Range:
    """Query parameters shared by every collection: time range, robot, pagination."""

    def __init__(
        self,
        start: float | None = Query(None, alias="from", description="timestamp >= from (s)"),
        end: float | None = Query(None, alias="to", description="timestamp < to (s)"),
        robot: str | None = Query(None, max_length=64, description="only this robot"),
        limit: int = Query(100, ge=1, le=MAX_PAGE),
        offset: int = Query(0, ge=0, le=ID_MAX),
        after_id: int | None = Query(
            None, ge=0, le=ID_MAX, description="only ids above; orders by id"
        ),
    ) -> None:
        self.start, self.end, self.robot = start, end, robot
        self.limit, self.offset, self.after_id = limit, offset, after_id


UPGRADE = Header(
    None,
    description=(
        "`websocket` (with the WebSocket handshake: 101, then one text frame per new record, "
        "query parameter `after_id` first sends the stored records after that id) or "
        "`callback` (with `Callback`: 201, the subscription); other protocols are ignored"
    ),
)
CALLBACK = Header(
    None, description=("with `Upgrade: callback`: the http(s) URI each new record is posted to")
)
IN_RANGE = Depends()  # a Range, from the query


def subscription_document(prefix: str, item: dict[str, Any]) -> dict[str, Any]:
    """A subscription (``Hub.describe``) as JSON, with its path under ``prefix``."""
    return {**item, "href": f"{prefix}/subscriptions/{item['id']}"}


def subscription_answer(
    service: StoreService,
    answers: Answers,
    request: Request,
    item: dict[str, Any],
    status: int = 200,
    media: str | None = None,
) -> Response:
    """A subscription, as a created one (201) or as a GET of it answers."""
    href = f"{service.prefix}/subscriptions/{item['id']}"
    headers = {"Link": related(item["resource"])}
    if status == 201:
        headers["Location"] = href
    linked = service.linked
    return answers.represent(
        request,
        subscription_document(service.prefix, item),
        lambda links: linked.document(linked.subscription(links, item)),
        status=status,
        headers=headers,
        media=media,
    )


def add_routes(
    service: StoreService, routes: Routes, answers: Answers, feeds: list[subscriptions.Collection]
) -> None:
    """The routes of the collections ``feeds`` (raw first) and of the errors."""
    settings, prefix, linked = service.settings, service.prefix, service.linked
    check_token = service.guard.check
    reader = [Depends(service.guard.reader)]
    reads = read_answers(settings)

    def page(
        request: Request,
        media: str,
        collection: subscriptions.Collection,
        time_column: Any,
        convert: Callable[[Any], dict[str, Any]],
        q: Range,
    ) -> Response:
        table = collection.table
        query = select(table)
        if q.start is not None:
            query = query.where(time_column >= q.start)
        if q.end is not None:
            query = query.where(time_column < q.end)
        if q.robot is not None:
            query = query.where(table.c.robot == q.robot)
        if q.after_id is not None:
            query = query.where(table.c.id > q.after_id).order_by(table.c.id)
        else:
            query = query.order_by(time_column, table.c.id)
        with request.app.state.engine.connect() as conn:
            rows = conn.execute(query.limit(q.limit + 1).offset(q.offset)).all()
        headers = {}
        next_url = None
        if len(rows) > q.limit:
            next_url = str(request.url.include_query_params(offset=q.offset + q.limit))
            headers["Link"] = f'<{next_url}>; rel="next"'
        rows = rows[: q.limit]
        path = request.url.path

        def turtle(links: Links) -> str:
            blocks = [collection.turtle(links, row) for row in rows]
            members = [links(f"{collection.path}/{int(row.id)}") for row in rows]
            return linked.page(links, path, str(request.url), members, blocks, next_url)

        document = {
            "items": [convert(row) for row in rows] if media == "json" else [],
            "offset": q.offset,
            "limit": q.limit,
            "next": next_url,
        }
        return answers.represent(request, document, turtle, headers=headers, media=media)

    def one(
        request: Request,
        table: Table,
        record_id: int,
        convert: Callable[[Any], dict[str, Any]],
        turtle: Callable[[Links, Any], str],
    ) -> Response:
        media = answers.media_of(request)
        row = None
        if 0 <= record_id <= ID_MAX:  # no id beyond 64 bits exists (the drivers refuse one)
            with request.app.state.engine.connect() as conn:
                row = conn.execute(select(table).where(table.c.id == record_id)).first()
        if row is None:
            raise HTTPException(404, f"no record {record_id}")
        return answers.represent(
            request, convert(row), lambda links: linked.one(turtle(links, row)), media=media
        )

    async def subscribe_callback(
        request: Request, collection: subscriptions.Collection, callback: str | None
    ) -> Response:
        check_token(request.headers.get("authorization"))
        try:  # resolving the host may wait for DNS: not in the event loop
            checked, _ = await run_in_threadpool(
                callback_targets.destinations, callback, settings.callback_hosts
            )
        except callback_targets.CallbackRefused as exc:
            raise HTTPException(400, str(exc)) from None
        media = answers.media_of(request)
        item = await request.app.state.hub.create_callback(
            collection, checked.uri, media, links_of(request)
        )
        return subscription_answer(service, answers, request, item, status=201, media=media)

    async def listing(
        request: Request,
        collection: subscriptions.Collection,
        q: Range,
        upgrade: str | None,
        callback: str | None,
        time_column: Any,
        convert: Callable[[Any], dict[str, Any]],
    ) -> Response:
        if upgrade is not None and request.method == "GET":
            protocols = {p.strip().partition("/")[0].lower() for p in upgrade.split(",")}
            if "websocket" in protocols:  # the handshake reached us as a plain request
                raise HTTPException(
                    426,
                    "a WebSocket subscription needs the WebSocket handshake "
                    "(Connection: Upgrade, Sec-WebSocket-Key, Sec-WebSocket-Version: 13)",
                    {"Upgrade": "websocket", "Connection": "Upgrade"},
                )
            if "callback" in protocols:
                return await subscribe_callback(request, collection, callback)
        media = answers.media_of(request)
        return await run_in_threadpool(page, request, media, collection, time_column, convert, q)

    listings = collection_answers(settings)
    raw_records, raw = service.raw_records, feeds[0]

    async def list_raw(
        request: Request,
        q: Range = IN_RANGE,
        upgrade: str | None = UPGRADE,
        callback: str | None = CALLBACK,
    ) -> Response:
        return await listing(
            request, raw, q, upgrade, callback, raw_records.c.source_ts, raw_document
        )

    routes.resource(
        prefix + "/records",
        list_raw,
        "records",
        listings,
        f"Raw {service.raw_type} records by source timestamp range; subscriptions",
        "RawPage",
        dependencies=reader,
    )
    routes.options(prefix + "/records", "records", COLLECTION)

    async def get_raw(request: Request, record_id: int) -> Response:
        return await run_in_threadpool(
            one, request, raw_records, record_id, raw_document, linked.raw_record
        )

    # {record_id:int}: only digits reach the route (/records/batch is the batch's, 405 on GET)
    routes.resource(
        prefix + "/records/{record_id:int}",
        get_raw,
        "raw_record",
        (*reads, 404),
        f"One raw {service.raw_type} record",
        "RawRecord",
        dependencies=reader,
    )
    routes.options(prefix + "/records/{record_id:int}", "raw_record", READ)
    add_error_routes(service, routes, answers, reads)

    def refined_routes(refinement: Refinement, collection: subscriptions.Collection) -> None:
        path = f"{prefix}/{refinement.name}"
        table = refinement.table

        def convert(row: Any) -> dict[str, Any]:
            return refined_document(refinement, row)

        async def list_refined(
            request: Request,
            q: Range = IN_RANGE,
            upgrade: str | None = UPGRADE,
            callback: str | None = CALLBACK,
        ) -> Response:
            return await listing(
                request, collection, q, upgrade, callback, table.c.timestamp, convert
            )

        async def get_refined(request: Request, record_id: int) -> Response:
            return await run_in_threadpool(
                one, request, table, record_id, convert, collection.turtle
            )

        routes.resource(
            path,
            list_refined,
            f"{refinement.name}_records",
            listings,
            f"{refinement.name} records by source timestamp range; subscriptions",
            f"Page_{refinement.name}",
            dependencies=reader,
        )
        routes.resource(
            path + "/{record_id:int}",
            get_refined,
            f"{refinement.name}_record",
            (*reads, 404),
            f"One {refinement.name} record",
            f"Refined_{refinement.name}",
            dependencies=reader,
        )
        routes.options(path, f"{refinement.name}_records", READ)
        routes.options(path + "/{record_id:int}", f"{refinement.name}_record", READ)

    for refinement, collection in zip(service.refinements, feeds[1:], strict=True):
        refined_routes(refinement, collection)
    for collection in feeds:
        add_websocket_route(service, routes, answers, collection)


def after_id(value: str | None) -> int | None:
    """The ``after_id`` of a WebSocket subscription: 400 unless it is an id."""
    if value is None:
        return None
    if not (re.fullmatch(r"[0-9]{1,19}", value) and int(value) <= ID_MAX):
        raise HTTPException(400, f"after_id {value!r}: an id (0 to {ID_MAX})")
    return int(value)


def add_websocket_route(
    service: StoreService, routes: Routes, answers: Answers, collection: subscriptions.Collection
) -> None:
    """Subscriptions to ``collection`` by WebSocket (R0.12-R0.17, R1.8)."""
    settings = service.settings

    async def subscribe(websocket: WebSocket) -> None:
        refusal = None
        try:
            if settings.protect_reads:
                service.guard.check(websocket.headers.get("authorization"))
            after = after_id(websocket.query_params.get("after_id"))
            media = answers.media_of(websocket)
        except HTTPException as exc:
            refusal = problem(exc.status_code, exc.detail, dict(exc.headers or {}))
        if refusal is not None:
            if "websocket.http.response" in websocket.scope.get("extensions", {}):
                await websocket.send_denial_response(refusal)
            else:
                await websocket.close(code=1008)
            return
        hub = websocket.app.state.hub
        # the newest id is read before the handshake ends: a client may write the moment
        # its connection is open, and those records are new to its subscription
        position = after if after is not None else await hub.newest(collection)
        await websocket.accept()
        subscriber = subscriptions.WebSocketSubscriber(
            websocket, hub, collection, media, links_of(websocket), position
        )
        await subscriber.serve()

    routes.app.add_api_websocket_route(collection.path, subscribe, name=f"ws_{collection.name}")
