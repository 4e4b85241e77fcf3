"""The largest request body ``spl configure`` takes (docs/configure.md, "Limits").

Why a middleware rather than a check in each endpoint: FastAPI reads a declared body
(``Body()``) before the endpoint runs, so an endpoint cannot refuse a large body before
the server has waited for all of it. This ASGI middleware sits in front of the
application: a body announced larger than the limit (``Content-Length``) is answered
413 before any of it is read, and a body without a length (chunked) is counted as it is
read and refused with 413 at the first read past the limit. The answer closes the
connection, so the server reads no more of the body; so does the answer to a chunked
body the endpoint did not read to its end (one that takes no body), which the server
would otherwise read on and throw away.
"""

from __future__ import annotations

import json

from fastapi import HTTPException
from starlette.types import ASGIApp, Message, Receive, Scope, Send

# The largest body any endpoint takes, with room to spare: the largest is an imported
# selection or capability file, 30 KB for a selection of automotive01's 2,513 features.
MAX_BODY = 2**20


class BodyTooLarge(HTTPException):
    """A read past the limit, raised in the application; :class:`BodyLimit` answers."""

    def __init__(self, limit: int) -> None:
        super().__init__(413, f"the request body has more than {limit} bytes")


class BodyLimit:
    """ASGI middleware: no request body over ``limit`` bytes reaches the application."""

    def __init__(self, app: ASGIApp, limit: int = MAX_BODY) -> None:
        self.app = app
        self.limit = limit

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        chunked = False
        for name, value in scope["headers"]:
            if name == b"content-length" and value.isdigit() and int(value) > self.limit:
                reason = f"the request body has {int(value)} bytes; at most {self.limit} are taken"
                await refuse(send, reason)
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
            await refuse(send, f"the request body has more than {self.limit} bytes")


async def refuse(send: Send, reason: str) -> None:
    """413 with the reason, as the API's other refusals (``{"error": ...}``), closing
    the connection."""
    body = json.dumps({"error": reason}).encode()
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
