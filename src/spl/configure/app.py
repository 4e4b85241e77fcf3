"""The configurator's web application: one page and a JSON API (docs/configure.md).

Why a static page and a JSON API on FastAPI: FastAPI is what the generated data
services already run on (docs/services.md), so the stack adds no new framework; the page
is one Jinja2 template and one vendored script, so installing spl needs no Node build.
A decision is answered with only the rows whose state changed, which the script patches
in place: a 2,513-feature tree is rendered once, not re-sent per click.

Each browser gets a session (a random cookie); sessions share the workspace's models and
solver but none of their choices. Nothing is written into the product line except by
``POST /api/save`` with a validated name.
"""

from __future__ import annotations

import io
import secrets
import threading
import time
import zipfile
from collections import OrderedDict
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from fastapi import Body, FastAPI, Query, Request
from fastapi.responses import HTMLResponse, JSONResponse, Response
from jinja2 import Environment, FileSystemLoader, select_autoescape
from starlette.middleware.trustedhost import TrustedHostMiddleware

from spl.configure.body_limit import MAX_BODY, BodyLimit
from spl.configure.selection_file import (
    read_capabilities_text,
    read_selection_text,
    selection_text,
)
from spl.configure.session import Impossible, InputError, Session, valid_name
from spl.configure.workspace import Workspace
from spl.core.diagnostics import ModelError

if TYPE_CHECKING:
    from spl.pipeline import Derivation

HERE = Path(__file__).resolve().parent
COOKIE = "spl_configure_session"
# sessions kept (each holds its choices and at most one derived bundle): a client that
# never sends its cookie back must not grow the server without bound
SESSIONS = 64
STATIC = {"configure.js": "text/javascript", "configure.css": "text/css"}


def create_app(
    workspace: Workspace, hosts: list[str] | None = None, max_body: int = MAX_BODY
) -> FastAPI:
    """The application serving ``workspace`` to any number of independent sessions.
    ``hosts``: the only Host headers answered (a page of another site that makes its
    browser resolve its own name to 127.0.0.1 is refused: DNS rebinding); None, any.
    ``max_body``: the largest request body in bytes, 413 beyond (body_limit.py)."""
    app = FastAPI(title=f"spl configure {workspace.title}", docs_url=None, redoc_url=None)
    if hosts is not None:
        app.add_middleware(TrustedHostMiddleware, allowed_hosts=hosts)
    app.add_middleware(BodyLimit, limit=max_body)  # outermost: before anything reads
    sessions: OrderedDict[str, Session] = OrderedDict()
    sessions_guard = threading.Lock()
    templates = Environment(
        loader=FileSystemLoader(HERE / "templates"), autoescape=select_autoescape(["html"])
    )

    def session_of(request: Request) -> tuple[Session, str | None]:
        """The request's session, and the new cookie value when one was made."""
        token = request.cookies.get(COOKIE, "")
        with sessions_guard:
            found = sessions.get(token)
            if found is not None:
                sessions.move_to_end(token)
                return found, None
            token = secrets.token_urlsafe(18)
            session = sessions[token] = Session(workspace)
            if len(sessions) > SESSIONS:  # the least recently used one goes
                sessions.popitem(last=False)
            if workspace.initial is not None:
                session.start_from(workspace.initial)
            return session, token

    def reply(request: Request, make: Any, status: int = 200, locked: bool = True) -> Response:
        """Run ``make(session)``; its errors become the statuses the page shows:
        409 with the explanation for an impossible decision, 422 for a bad value.
        One request of a session runs at a time (its page may send two), unless
        ``locked`` is false (counting: it reads a propagation and changes nothing)."""
        session, token = session_of(request)
        started = time.perf_counter()
        try:
            if locked:
                with session.lock:
                    body = make(session)
            else:
                body = make(session)
        except Impossible as exc:
            body, status = {"error": "no product would be left", "explanation": exc.lines}, 409
        except InputError as exc:
            body, status = {"error": str(exc)}, 422
        except ModelError as exc:
            problems = [str(d) for d in exc.diagnostics]
            body, status = {"error": "; ".join(problems), "problems": problems}, 422
        response = body if isinstance(body, Response) else JSONResponse(body, status)
        # the time the answer took here, for bench/configure_latency.py and browser tools
        elapsed = (time.perf_counter() - started) * 1000
        response.headers["Server-Timing"] = f"app;dur={elapsed:.2f}"
        if token is not None:
            response.set_cookie(COOKIE, token, httponly=True, samesite="strict")
        return response

    @app.get("/", response_class=HTMLResponse)
    def page(request: Request) -> Response:
        def render(session: Session) -> Response:
            view = session.view(full=True)
            html = templates.get_template("page.html").render(
                workspace=workspace, view=view, states=view["states"]
            )
            return HTMLResponse(html)

        return reply(request, render)

    @app.get("/static/{name}")
    def static(name: str) -> Response:
        if name not in STATIC:
            return JSONResponse({"error": f"no file {name}"}, 404)
        return Response((HERE / "static" / name).read_bytes(), media_type=STATIC[name])

    @app.get("/api/state")
    def state(request: Request) -> Response:
        return reply(request, lambda s: s.view(full=True))

    @app.post("/api/decide")
    def decide(request: Request, feature: str = Body(), action: str = Body()) -> Response:
        def run(session: Session) -> dict:
            session.decide(feature, action)
            return session.view(full=False)

        return reply(request, run)

    @app.get("/api/explain")
    def explain(request: Request, feature: str = Query()) -> Response:
        return reply(request, lambda s: {"feature": feature, "lines": s.explanation(feature)})

    @app.get("/api/count")
    def count(request: Request, exhaustive: bool = Query(False)) -> Response:
        from spl.configure.session import COUNT_SECONDS, FOLLOW_UP_SECONDS

        seconds = COUNT_SECONDS if exhaustive else FOLLOW_UP_SECONDS

        def run(session: Session) -> dict:
            with session.lock:
                propagation = session.propagation()
            return {"products": session.count(propagation, seconds)}

        return reply(request, run, locked=False)

    def changing(change: Any) -> Any:
        def run(session: Session) -> dict:
            change(session)
            return session.view(full=False)

        return run

    @app.post("/api/attribute")
    def attribute(request: Request, key: str = Body(), value: str = Body()) -> Response:
        return reply(request, changing(lambda s: s.set_attribute(key, value)))

    @app.post("/api/sharing")
    def sharing(request: Request, feature: str = Body(), mode: str = Body()) -> Response:
        return reply(request, changing(lambda s: s.set_sharing(feature, mode)))

    @app.post("/api/deployment")
    def deployment(
        request: Request, container: str = Body(), key: str = Body(), value: str = Body()
    ) -> Response:
        return reply(request, changing(lambda s: s.set_deployment(container, key, value)))

    @app.post("/api/undo")
    def undo(request: Request) -> Response:
        return reply(request, changing(lambda s: s.undo()))

    @app.post("/api/redo")
    def redo(request: Request) -> Response:
        return reply(request, changing(lambda s: s.redo()))

    @app.get("/api/selection.yaml")
    def export(request: Request, name: str | None = Query(None)) -> Response:
        def run(session: Session) -> Response:
            if name is not None and not valid_name(name):
                raise InputError(f"{name!r} is not a product name (letters, digits, '_')")
            text = selection_text(session.selection(name))
            filename = f"{session.selection(name).name}.yaml"
            disposition = f'attachment; filename="{filename}"'
            return Response(text, media_type="application/yaml",
                            headers={"Content-Disposition": disposition})  # fmt: skip

        return reply(request, run)

    @app.post("/api/selection")
    def import_selection(
        request: Request, text: str = Body(), filename: str = Body("selection.yaml")
    ) -> Response:
        return reply(request, changing(lambda s: s.replace(read_selection_text(s, text, filename))))

    @app.post("/api/capabilities")
    def import_capabilities(
        request: Request, text: str = Body(), filename: str = Body("robot.yaml")
    ) -> Response:
        return reply(
            request,
            changing(lambda s: s.use_capabilities(read_capabilities_text(text, filename))),
        )

    @app.post("/api/save")
    def save(request: Request, name: str = Body(embed=True)) -> Response:
        def run(session: Session) -> dict:
            line = workspace.line
            if line is None:
                raise InputError("a bare feature model has no products folder to save into")
            if not valid_name(name):
                raise InputError(f"{name!r} is not a product name (letters, digits, '_')")
            target = line.directory / "products" / f"{name}.yaml"
            if target.exists():
                raise InputError(f"products/{name}.yaml exists: choose another name")
            target.parent.mkdir(exist_ok=True)
            target.write_text(selection_text(session.selection(name)), encoding="utf-8")
            return {"saved": f"products/{name}.yaml"}

        return reply(request, run)

    @app.get("/api/architecture")
    def architecture(request: Request) -> Response:
        def run(session: Session) -> dict:
            derivation = _derived(session)
            from spl.configure.drawing import architecture_svg
            from spl.resolver.resolution.engine import summary_lines

            resolution = derivation.resolution
            return {
                "svg": architecture_svg(resolution),
                "summary": summary_lines(resolution),
                "warnings": [str(w) for w in derivation.warnings],
                "product": resolution.product.name,
            }

        return reply(request, run)

    @app.get("/api/bundle.zip")
    def bundle_zip(request: Request) -> Response:
        def run(session: Session) -> Response:
            derivation = _derived(session)
            name = derivation.resolution.product.name
            return Response(
                zipped(derivation.bundle.files),
                media_type="application/zip",
                headers={"Content-Disposition": f'attachment; filename="{name}.zip"'},
            )

        return reply(request, run)

    def _derived(session: Session) -> Derivation:
        """The complete selection derived (resolved, its bundle generated, its warnings
        said as every command says them), once per selection."""
        if workspace.line is None:
            raise InputError("a bare feature model is analysed only: it has no architecture")
        if not session.complete():
            raise Impossible(["the selection is not complete: decide the open features"])
        selection = session.selection()
        key = selection_text(selection)
        if key not in session.derived:
            from spl import pipeline

            session.derived.clear()  # keep one: a bundle can be megabytes
            session.derived[key] = pipeline.derive(workspace.line, selection)
        return cast("Derivation", session.derived[key])

    return app


def zipped(files: dict[str, bytes]) -> bytes:
    """A bundle's files in a zip, by path, with a fixed date: the same bundle gives the
    same bytes."""
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for path in sorted(files):
            info = zipfile.ZipInfo(path, date_time=(1980, 1, 1, 0, 0, 0))
            info.external_attr = 0o644 << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            archive.writestr(info, files[path])
    return out.getvalue()
