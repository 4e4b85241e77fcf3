"""How a service answers (docs/services.md, "Linked Robotic Things"): JSON or Turtle as
the Accept header asks, with an ETag and 304 for a client that already has the body,
and problems as ``{"status", "detail"}``. The Turtle itself is linked.py's, of the
store's own resources (``StoreDocuments``, which the product's ``linked.py`` makes):
the routes take it from the service, never by import.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable
from typing import Any

from fastapi import HTTPException, Request, WebSocket
from fastapi.responses import JSONResponse, Response

from .turtle import Links, NotAcceptable

# One encoder for every answer: json.dumps with options builds a new one per call.
JSON = json.JSONEncoder(separators=(",", ":"), allow_nan=False)
TURTLE_TYPE = "text/turtle; charset=utf-8"


def etag(body: bytes) -> str:
    """The validator of a representation: the same body always has the same tag."""
    return '"' + hashlib.sha256(body).hexdigest()[:32] + '"'


def problem(status: int, reason: Any, headers: dict[str, str] | None = None) -> JSONResponse:
    """Every error answer of a service, so that clients read one shape of reason."""
    return JSONResponse({"status": status, "detail": reason}, status_code=status, headers=headers)


def related(*paths: str) -> str:
    """A Link header from a resource to its sub-resources (R0.6)."""
    return ", ".join(f'<{p}>; rel="related"' for p in paths)


def links_of(request: Request | WebSocket) -> Links:
    """The base of the Turtle's IRIs: the URL the client used to reach the service."""
    base = str(request.base_url)
    if base.startswith("ws"):  # ws:// and wss:// name the same resources as http(s)://
        base = "http" + base[2:]
    return Links(base)


class Answers:
    """The representations of one service: ``negotiate`` is its process's content
    negotiation (linked.py holds its remembered choices)."""

    def __init__(self, negotiate: Callable[[str | None], str]) -> None:
        self.negotiate = negotiate

    def media_of(self, request: Request | WebSocket) -> str:
        """``"turtle"`` or ``"json"`` as the Accept header asks; 406 when neither fits."""
        try:
            return self.negotiate(request.headers.get("accept"))
        except NotAcceptable:
            raise HTTPException(
                406,
                f"not acceptable: {request.headers.get('accept')!r}; this resource is "
                "available as text/turtle or application/json",
            ) from None

    def represent(
        self,
        request: Request,
        document: Any,
        turtle: Callable[[Links], str],
        status: int = 200,
        headers: dict[str, str] | None = None,
        media: str | None = None,
    ) -> Response:
        """JSON or Turtle (content negotiation) with an ETag; a matching If-None-Match
        gets 304 without a body."""
        if media is None:
            media = self.media_of(request)
        if media == "json":
            body, media_type = JSON.encode(document).encode(), "application/json"
        else:
            body, media_type = turtle(links_of(request)).encode(), TURTLE_TYPE
        tag = etag(body)
        headers = {"ETag": tag, "Vary": "Accept", **(headers or {})}
        if status == 200 and tag in request.headers.get("if-none-match", ""):
            return Response(status_code=304, headers=headers)
        return Response(body, status_code=status, headers=headers, media_type=media_type)
