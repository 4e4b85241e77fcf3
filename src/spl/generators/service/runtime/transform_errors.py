"""The transform errors of a service (docs/services.md, "Transformer"): the raw records
the transformer could not convert, with the reason, a page at a time. Unlike the
collections (reads.py) nobody subscribes to them, and they are ordered by id only.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from fastapi import Depends, Query, Request
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import Response
from sqlalchemy import select

from .answers import Answers
from .routes import ID_MAX, MAX_PAGE, READ, Routes
from .turtle import Links

if TYPE_CHECKING:
    from .service import StoreService


def error_document(row: Any) -> dict[str, Any]:
    """A raw record the transformer could not convert, with the reason, as JSON."""
    return {
        "id": row.id,
        "refinement": row.refinement,
        "raw_id": row.raw_id,
        "message": row.message,
    }


def add_error_routes(
    service: StoreService, routes: Routes, answers: Answers, reads: tuple[int, ...]
) -> None:
    """The raw records the transformer could not convert, with the reason (``reads``:
    the answers of a read, to which a bad page or offset adds 400)."""
    errors, linked = service.transform_errors, service.linked

    def page(request: Request, media: str, limit: int, offset: int) -> Response:
        query = select(errors).order_by(errors.c.id)
        with request.app.state.engine.connect() as conn:
            rows = conn.execute(query.limit(limit + 1).offset(offset)).all()
        next_url = (
            str(request.url.include_query_params(offset=offset + limit))
            if len(rows) > limit
            else None
        )
        headers = {"Link": f'<{next_url}>; rel="next"'} if next_url else {}
        rows = rows[:limit]
        path = request.url.path

        def turtle(links: Links) -> str:
            blocks = [linked.error_record(links, row) for row in rows]
            members = [linked.iri(links.url(path) + f"#e{int(row.id)}") for row in rows]
            return linked.page(links, path, str(request.url), members, blocks, next_url)

        return answers.represent(
            request,
            {
                "items": [error_document(r) for r in rows],
                "offset": offset,
                "limit": limit,
                "next": next_url,
            },
            turtle,
            headers=headers,
            media=media,
        )

    async def list_errors(
        request: Request,
        limit: int = Query(100, ge=1, le=MAX_PAGE),
        offset: int = Query(0, ge=0, le=ID_MAX),
    ) -> Response:
        media = answers.media_of(request)
        return await run_in_threadpool(page, request, media, limit, offset)

    routes.resource(
        service.prefix + "/errors",
        list_errors,
        "errors",
        (*reads, 400),
        "Raw records the transformer could not convert, with the reason",
        "ErrorPage",
        dependencies=[Depends(service.guard.reader)],
    )
    routes.options(service.prefix + "/errors", "errors", READ)
