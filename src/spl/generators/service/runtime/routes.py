"""The routes of a service as its OpenAPI document lists them (runtime/contract.py): one
route per method, each with its own operation id and its documented answers, an
OPTIONS route answering Allow on every path, and the error answers every route shares
(400 with the reasons of a validation, 405 with Allow, 500 without details).
"""

from __future__ import annotations

import inspect
import logging
import re
from collections.abc import Callable
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse, Response
from starlette.exceptions import HTTPException as StarletteHTTPException

from . import contract
from .answers import problem

METHOD_ORDER = ("GET", "HEAD", "POST", "DELETE", "OPTIONS")
READ = "GET, HEAD, OPTIONS"
COLLECTION = "GET, HEAD, POST, OPTIONS"
MAX_PAGE = 1000  # records in one page of a collection
ID_MAX = 2**63 - 1  # ids and offsets are 64-bit in SQLite and PostgreSQL alike


def head_answers(statuses: tuple[int, ...]) -> tuple[int, ...]:
    """The answers of a HEAD: it creates nothing and switches no protocol."""
    return tuple(s for s in statuses if s not in (101, 201, 426))


def path_parameters(path: str) -> list[tuple[str, str]]:
    """(name, convertor) of each parameter of a route's path: ``{record_id:int}`` is
    ``("record_id", "int")``, ``{field}`` is ``("field", "")``."""
    return [
        (name, convertor)
        for name, _, convertor in (p.partition(":") for p in re.findall(r"{([^}]+)}", path))
    ]


class Routes:
    """Adds the routes of one service to its application ``app``."""

    def __init__(self, app: FastAPI) -> None:
        self.app = app

    def allowed_methods(self, path: str) -> str:
        """Every method some route offers on ``path`` (a 405 must list them all in Allow)."""
        methods: set[str] = set()
        for route in self.app.routes:
            regex = getattr(route, "path_regex", None)
            if regex is not None and regex.match(path):
                methods |= set(getattr(route, "methods", None) or ())
        return ", ".join(m for m in METHOD_ORDER if m in methods)

    def resource(
        self,
        path: str,
        endpoint: Callable[..., Any],
        name: str,
        statuses: tuple[int, ...],
        summary: str,
        body: str | None = None,
        methods: tuple[str, ...] = ("GET", "HEAD"),
        dependencies: list[Any] | None = None,
        token: bool = False,
        **kwargs: Any,
    ) -> None:
        """One route per method, each with its own operation id and documented answers
        (``body``: the schema of its JSON representation; ``token``: always needs one)."""
        for method in methods:
            answers = head_answers(statuses) if method == "HEAD" else statuses
            self.app.add_api_route(
                path,
                endpoint,
                methods=[method],
                name=f"{method.lower()}_{name}",
                operation_id=f"{method.lower()}_{name}",
                summary=summary,
                dependencies=dependencies,
                openapi_extra={
                    contract.STATUSES: answers,
                    contract.BODY: body,
                    contract.TOKEN: token,
                },
                **kwargs,
            )

    def options(self, path: str, name: str, allow: str) -> None:
        """OPTIONS on ``path``: 204 with ``allow``."""

        async def answer(**_parameters: Any) -> Response:
            return Response(status_code=204, headers={"Allow": allow})

        # the path's parameters, so that the OpenAPI document declares them; a path of
        # ids ({record_id:int}) matches digits only: anything else is no resource (404)
        parameters = path_parameters(path)
        answer.__signature__ = inspect.Signature(  # type: ignore[attr-defined]
            [
                inspect.Parameter(
                    name_,
                    inspect.Parameter.KEYWORD_ONLY,
                    annotation=int if convertor == "int" else str,
                )
                for name_, convertor in parameters
            ]
        )
        statuses = (204, 404) if any(c == "int" for _, c in parameters) else (204,)
        self.app.add_api_route(
            path,
            answer,
            methods=["OPTIONS"],
            name=f"options_{name}",
            operation_id=f"options_{name}",
            status_code=204,
            summary=f"Allowed methods: {allow}",
            openapi_extra={contract.STATUSES: statuses, contract.ALLOW: allow},
        )

    def answer_errors(self, log: logging.Logger) -> None:
        """The error answers of every route, as problems (``log``: the failures' logger)."""

        async def bad_request(_request: Request, exc: Exception) -> JSONResponse:
            assert isinstance(exc, RequestValidationError)
            reasons = [
                {"where": "/".join(str(p) for p in error["loc"]), "problem": error["msg"]}
                for error in exc.errors()
            ]
            return problem(400, reasons)

        async def http_error(request: Request, exc: Exception) -> JSONResponse:
            assert isinstance(exc, StarletteHTTPException)
            headers = dict(getattr(exc, "headers", None) or {})
            if exc.status_code == 405:
                headers["Allow"] = self.allowed_methods(request.url.path)
            return problem(exc.status_code, exc.detail, headers)

        async def server_error(_request: Request, exc: Exception) -> JSONResponse:
            log.exception("request failed", exc_info=exc)
            return problem(500, "internal server error")

        self.app.add_exception_handler(RequestValidationError, bad_request)
        self.app.add_exception_handler(StarletteHTTPException, http_error)
        self.app.add_exception_handler(Exception, server_error)
