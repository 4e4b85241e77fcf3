"""The runtime's door of a service, imported directly (docs/services.md, "Body limit"
and "Tokens"): BodyLimit answers 413 to a body announced or grown past the limit before
the application sees more of it, and closes the connection; the guard asks writers (and
readers when reads are protected) for the bearer token; a write route checks the token
before it validates the body. The live tests run the same code inside real services
(tests/live/test_service_body_limits.py)."""

from __future__ import annotations

import asyncio
import json
from typing import Any

import httpx
from fastapi import Depends, FastAPI, Request
from fastapi.responses import JSONResponse
from pydantic import BaseModel

from spl.generators.service.runtime.access import BodyLimit, Guard, Message, write_route

LIMIT = 10


class Reader:
    """An ASGI application that reads the whole body and answers how much it got."""

    def __init__(self) -> None:
        self.called = False

    async def __call__(self, scope: Message, receive: Any, send: Any) -> None:
        self.called = True
        size, more = 0, True
        while more:
            message = await receive()
            size += len(message.get("body", b""))
            more = message.get("more_body", False)
        await send({"type": "http.response.start", "status": 200, "headers": []})
        await send({"type": "http.response.body", "body": str(size).encode()})


def _run(app: Any, headers: list[tuple[bytes, bytes]], chunks: list[bytes]) -> list[Message]:
    """The messages ``app`` sends for a request of ``chunks`` (the last one ends it)."""
    sent: list[Message] = []
    pending = [
        {"type": "http.request", "body": c, "more_body": i < len(chunks) - 1}
        for i, c in enumerate(chunks)
    ]

    async def receive() -> Message:
        return pending.pop(0) if pending else {"type": "http.disconnect"}

    async def send(message: Message) -> None:
        sent.append(message)

    scope = {"type": "http", "method": "POST", "path": "/", "headers": headers}
    asyncio.run(app(scope, receive, send))
    return sent


def _answer(sent: list[Message]) -> tuple[int, dict[bytes, bytes], bytes]:
    start, *bodies = sent
    return start["status"], dict(start["headers"]), b"".join(m["body"] for m in bodies)


def test_an_announced_body_over_the_limit_is_refused_unread() -> None:
    inner = Reader()
    status, headers, body = _answer(
        _run(BodyLimit(inner, LIMIT), [(b"content-length", b"11")], [b"x" * 11])
    )
    assert not inner.called
    assert status == 413 and headers[b"connection"] == b"close"
    assert json.loads(body) == {
        "status": 413,
        "detail": "the body has 11 bytes; at most 10 are taken",
    }


def test_a_chunked_body_growing_past_the_limit_is_refused_and_the_connection_closed() -> None:
    inner = Reader()
    sent = _run(BodyLimit(inner, LIMIT), [(b"transfer-encoding", b"chunked")], [b"x" * 6] * 3)
    status, headers, body = _answer(sent)
    assert inner.called and status == 413 and headers[b"connection"] == b"close"
    assert json.loads(body)["detail"] == "the body has more than 10 bytes"


def test_a_body_within_the_limit_reaches_the_application_whole() -> None:
    status, _, body = _answer(
        _run(BodyLimit(Reader(), LIMIT), [(b"transfer-encoding", b"chunked")], [b"x" * 5] * 2)
    )
    assert (status, body) == (200, b"10")


class Item(BaseModel):
    n: int


def _service(protect_reads: bool) -> FastAPI:
    guard = Guard("sesame", protect_reads)
    app = FastAPI()

    async def post(request: Request, item: Item) -> JSONResponse:
        return JSONResponse({"n": item.n})

    app.router.add_api_route(
        "/items", post, methods=["POST"], route_class_override=write_route(guard)
    )

    @app.get("/items", dependencies=[Depends(guard.reader)])
    async def read() -> list[int]:
        return []

    return app


def _call(app: FastAPI, method: str, **kwargs: Any) -> httpx.Response:
    async def go() -> httpx.Response:
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://store") as client:
            return await client.request(method, "/items", **kwargs)

    return asyncio.run(go())


def test_a_write_needs_the_token_before_its_body_is_looked_at() -> None:
    app = _service(protect_reads=False)
    missing = _call(app, "POST", content=b"not json")
    assert missing.status_code == 401 and missing.json()["detail"] == "missing bearer token"
    assert missing.headers["www-authenticate"] == "Bearer"
    wrong = _call(app, "POST", json={"n": 1}, headers={"Authorization": "Bearer other"})
    assert (wrong.status_code, wrong.json()["detail"]) == (401, "invalid bearer token")
    right = _call(app, "POST", json={"n": 1}, headers={"Authorization": "bearer sesame"})
    assert (right.status_code, right.json()) == (200, {"n": 1})
    invalid = _call(app, "POST", json={"n": "one"}, headers={"Authorization": "Bearer sesame"})
    assert invalid.status_code == 422  # the service's handler turns this into its 400
    assert invalid.json()["detail"][0]["loc"] == ["body", "n"]


def test_reads_need_the_token_only_when_protected() -> None:
    assert _call(_service(protect_reads=False), "GET").status_code == 200
    protected = _service(protect_reads=True)
    assert _call(protected, "GET").status_code == 401
    answer = _call(protected, "GET", headers={"Authorization": "Bearer sesame"})
    assert answer.status_code == 200


def test_the_write_route_declares_its_token_and_body_for_the_contract() -> None:
    operation = _service(protect_reads=False).openapi()["paths"]["/items"]["post"]
    assert {p["name"] for p in operation["parameters"]} == {"authorization"}
    assert operation["requestBody"]["content"]["application/json"]["schema"] == {
        "$ref": "#/components/schemas/Item"
    }
