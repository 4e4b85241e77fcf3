"""The largest request body ``spl configure`` takes (docs/configure.md, "Limits").

Why a middleware rather than a check in each endpoint: FastAPI reads a declared body
(``Body()``) before the endpoint runs, so an endpoint cannot refuse a large body before
the server has waited for all of it. The middleware is the one every generated service
runs (:class:`spl.generators.service.runtime.access.BodyLimit`): a body announced larger
than the limit is answered 413 before any of it is read, a chunked one at the first read
past the limit, and the answer closes the connection. Here it names the request body
and answers as the configurator's other refusals do (``{"error": ...}``).
"""

from __future__ import annotations

from spl.generators.service.runtime import access

# The largest body any endpoint takes, with room to spare: the largest is an imported
# selection or capability file, 30 KB for a selection of automotive01's 2,513 features.
MAX_BODY = 2**20


class BodyLimit(access.BodyLimit):
    """No request body over ``limit`` bytes reaches the configurator."""

    BODY = "the request body"

    def __init__(self, app: access.ASGIApp, limit: int = MAX_BODY) -> None:
        super().__init__(app, limit)

    def answer(self, reason: str) -> dict[str, object]:
        return {"error": reason}
