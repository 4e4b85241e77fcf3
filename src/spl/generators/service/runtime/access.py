"""Who may write to and read from a store, and how a request is let in: a body
announced (Content-Length) larger than MAX_BODY is refused with 413 before anything
else and before any of it is read; then a write's bearer token (401); then its body,
read up to MAX_BODY bytes (413 as soon as a chunked one grows past it), against the
record model (400 with each place and problem)."""

from __future__ import annotations

import hmac
import json
from collections.abc import Awaitable, Callable, Coroutine, MutableMapping
from dataclasses import dataclass
from typing import Any, ClassVar, get_type_hints

from fastapi import Depends, Header, HTTPException, Request, Response
from fastapi.exceptions import RequestValidationError
from fastapi.routing import APIRoute
from pydantic import BaseModel, ValidationError


def check_token(authorization: str | None, expected: str) -> None:
    """401 unless ``authorization`` is ``Bearer <expected>`` (compared in constant time)."""
    scheme, _, token = (authorization or "").partition(" ")
    if scheme.lower() != "bearer" or not token:
        raise HTTPException(401, "missing bearer token", {"WWW-Authenticate": "Bearer"})
    if not hmac.compare_digest(token.strip().encode(), expected.encode()):
        raise HTTPException(401, "invalid bearer token", {"WWW-Authenticate": "Bearer"})


@dataclass(frozen=True)
class Guard:
    """The token writers present (and readers too when reads are protected), with the
    FastAPI dependencies that check it."""

    token: str
    protect_reads: bool

    def check(self, authorization: str | None) -> None:
        check_token(authorization, self.token)

    # async: no I/O here, so FastAPI need not hand them to its thread pool
    async def writer(self, authorization: str | None = Header(default=None)) -> None:
        self.check(authorization)

    async def reader(self, authorization: str | None = Header(default=None)) -> None:
        if self.protect_reads:
            self.check(authorization)


def is_json(content_type: str | None) -> bool:
    """application/json or application/*+json, as FastAPI decides it."""
    media = (content_type or "").partition(";")[0].strip().lower()
    return media == "application/json" or (
        media.startswith("application/") and media.endswith("+json")
    )


Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]
ASGIApp = Callable[[Message, Receive, Send], Awaitable[None]]


class BodyTooLarge(HTTPException):
    """Raised in the application by a read past the limit; the BodyLimit answers."""

    def __init__(self, limit: int) -> None:
        super().__init__(413, f"the body has more than {limit} bytes")


class BodyLimit:
    """ASGI middleware: no request body over ``limit`` bytes reaches the application.
    A larger Content-Length is answered 413 before anything is read; a body without one
    (chunked) is counted as the application reads it, and the first read past the limit
    ends the request with 413. The answer closes the connection, so the server reads
    no more of the body; so does the answer to a chunked body the endpoint did not read
    to its end (one that takes no body), which the server would read on otherwise.
    ``spl configure`` uses it too, naming the body and answering as its API does
    (a subclass's ``BODY`` and :meth:`answer`)."""

    BODY = "the body"

    def __init__(self, app: ASGIApp, limit: int) -> None:
        self.app = app
        self.limit = limit

    async def __call__(self, scope: Message, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        chunked = False
        for name, value in scope["headers"]:
            if name == b"content-length" and value.isdigit() and int(value) > self.limit:
                await self.refuse(
                    send, f"{self.BODY} has {int(value)} bytes; at most {self.limit} are taken"
                )
                return
            chunked = chunked or name == b"transfer-encoding"
        size, over, ended, started = 0, False, False, False

        async def limited() -> Message:
            nonlocal size, over, ended
            if over:
                raise BodyTooLarge(self.limit)
            message = await receive()
            if message["type"] == "http.request":
                size += len(message.get("body", b""))
                ended = not message.get("more_body", False)
                if size > self.limit:
                    over = True
                    raise BodyTooLarge(self.limit)
            return message

        async def sending(message: Message) -> None:
            nonlocal started
            if over:  # the application's own answer to the refused read: ours goes instead
                return
            if message["type"] == "http.response.start":
                started = True
                if chunked and not ended:  # an unread body of no known length: not read on
                    message = {
                        **message,
                        "headers": [*message.get("headers", ()), (b"connection", b"close")],
                    }
            await send(message)

        try:
            await self.app(scope, limited, sending)
        except Exception:
            if not over or started:
                raise
        if over and not started:
            await self.refuse(send, f"{self.BODY} has more than {self.limit} bytes")

    def answer(self, reason: str) -> dict[str, object]:
        """The JSON of a refusal: a problem document, as the service's other errors."""
        return {"status": 413, "detail": reason}

    async def refuse(self, send: Send, reason: str) -> None:
        body = json.dumps(self.answer(reason)).encode()
        await send(
            {
                "type": "http.response.start",
                "status": 413,
                "headers": [
                    (b"content-type", b"application/json"),
                    (b"content-length", str(len(body)).encode()),
                    (b"connection", b"close"),
                ],
            }
        )
        await send({"type": "http.response.body", "body": body})


class WriteRoute(APIRoute):
    """A write endpoint ``(request, <model>)``: the bearer token is checked first, then
    the body is validated against the model, as FastAPI does with ``Depends(writer)``
    and a body parameter, which are declared here for the OpenAPI document. The
    handler is this class's own: FastAPI's general one solved the dependencies anew
    on every request, most of a post's time; pydantic reads the JSON and validates
    it in one pass."""

    guard: ClassVar[Guard]

    def __init__(self, path: str, endpoint: Callable[..., Any], **kwargs: Any) -> None:
        if kwargs.pop("dependencies", None):
            raise TypeError("a WriteRoute runs no dependencies but its token check")
        super().__init__(path, endpoint, dependencies=[Depends(self.guard.writer)], **kwargs)

    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        endpoint, guard = self.endpoint, self.guard
        ((name, model),) = [
            (n, t)
            for n, t in get_type_hints(endpoint).items()
            if isinstance(t, type) and issubclass(t, BaseModel)
        ]

        async def handle(request: Request) -> Response:
            guard.check(request.headers.get("authorization"))
            body = await request.body()  # at most MAX_BODY bytes: BodyLimit
            try:
                if is_json(request.headers.get("content-type")):
                    value = model.model_validate_json(body)
                else:  # refused with the reason, as FastAPI refuses a body not JSON
                    value = model.model_validate(body)
            except ValidationError as exc:
                raise RequestValidationError(
                    [{**e, "loc": ("body", *e["loc"])} for e in exc.errors()]
                ) from None
            return await endpoint(request=request, **{name: value})

        return handle


def write_route(guard: Guard) -> type[WriteRoute]:
    """The route class of the write endpoints ``guard`` protects."""
    return type("WriteRoute", (WriteRoute,), {"guard": guard})
