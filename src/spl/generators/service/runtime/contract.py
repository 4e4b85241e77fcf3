"""The OpenAPI document of a store's service: FastAPI's paths and request
schemas, and for every operation exactly the answers it can give: each route names its
statuses (``STATUSES``) and the schema of its representation (``BODY``) when it is
added (routes.py); 400 (not FastAPI's 422) for invalid input, with the
reasons; the bearer token as a security scheme where it is needed.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from fastapi import FastAPI
from fastapi.openapi.utils import get_openapi

from .records import FieldSpec, Refinement

STATUSES = "x-spl-statuses"
BODY = "x-spl-body"
ALLOW = "x-spl-allow"
TOKEN = "x-spl-token"


def description(raw_type: str) -> str:
    """The service's description in its OpenAPI document."""
    return (
        f"First-order store of {raw_type} records and their refinements, as Linked Robotic "
        "Things: every resource is Turtle (text/turtle) unless the Accept header prefers "
        "JSON (application/json); 406 when it accepts neither. A GET of a collection "
        "(`records` or a refined type) with `Upgrade: websocket` opens a WebSocket that sends "
        "each new record as one text frame, in id order (query parameter `after_id=N` first "
        "sends the stored records with ids above N); with `Upgrade: callback` and `Callback: "
        "<http(s) URI>` (and the bearer token) it stores a subscription that posts each new "
        "record to that URI. Accept chooses JSON or Turtle for both."
    )


SCALARS = {
    "double": {"type": "number"},
    "int": {"type": "integer"},
    "string": {"type": "string"},
    "bool": {"type": "boolean"},
}
NULLABLE_STRING = {"anyOf": [{"type": "string"}, {"type": "null"}]}
INTEGER, NUMBER, STRING = {"type": "integer"}, {"type": "number"}, {"type": "string"}


def ref(name: str) -> dict[str, str]:
    return {"$ref": f"#/components/schemas/{name}"}


def obj(properties: dict[str, Any]) -> dict[str, Any]:
    return {"type": "object", "properties": properties, "required": list(properties)}


def _fields(fields: Iterable[FieldSpec]) -> dict[str, Any]:
    return {f.name: SCALARS[f.type] for f in fields}


def _page(item: str) -> dict[str, Any]:
    return obj(
        {
            "items": {"type": "array", "items": ref(item)},
            "offset": INTEGER,
            "limit": INTEGER,
            "next": NULLABLE_STRING,
        }
    )


def _href(**extra: Any) -> dict[str, Any]:
    return obj({"href": STRING, **extra})


TYPE_FIELDS = {"type": "array", "items": obj({"name": STRING, "type": STRING})}


def schemas(raw_fields: Iterable[FieldSpec], refinements: Iterable[Refinement]) -> dict[str, Any]:
    """The schemas of every representation, the store's own record types among them."""
    found: dict[str, Any] = {
        "Problem": obj(
            {
                "status": INTEGER,
                "detail": {"anyOf": [STRING, {"type": "array", "items": ref("Reason")}]},
            }
        ),
        "Reason": obj({"where": STRING, "problem": STRING}),
        "Created": obj({"id": INTEGER, "href": STRING}),
        "BatchCreated": obj(
            {
                "ids": {"type": "array", "items": INTEGER},
                "hrefs": {"type": "array", "items": STRING},
            }
        ),
        "Root": obj({"stores": {"type": "array", "items": STRING}}),
        "Store": obj(
            {
                "store": STRING,
                "raw": obj({"type": STRING, "fields": TYPE_FIELDS, "href": STRING}),
                "refined": {
                    "type": "array",
                    "items": obj(
                        {"type": STRING, "fields": TYPE_FIELDS, "period": NUMBER, "href": STRING}
                    ),
                },
                "errors": _href(),
                "subscriptions": _href(),
                "blueprint": _href(),
                "properties": _href(),
                "actions": _href(),
            }
        ),
        "RawRecord": obj(
            {
                "id": INTEGER,
                "robot": STRING,
                "timestamp": NUMBER,
                "received": NUMBER,
                "data": obj(_fields(raw_fields)),
                "key": NULLABLE_STRING,
            }
        ),
        "RawPage": _page("RawRecord"),
        "TransformError": obj(
            {"id": INTEGER, "refinement": STRING, "raw_id": INTEGER, "message": STRING}
        ),
        "ErrorPage": _page("TransformError"),
        "Subscription": obj(
            {
                "id": STRING,
                "type": {"type": "string", "enum": ["callback", "websocket"]},
                "resource": STRING,
                "media_type": {"type": "string", "enum": ["text/turtle", "application/json"]},
                "callback": NULLABLE_STRING,
                "created": NUMBER,
                "href": STRING,
            }
        ),
        "Subscriptions": obj({"items": {"type": "array", "items": ref("Subscription")}}),
        "Blueprint": obj(
            {
                "shapes": {
                    "type": "array",
                    "items": obj(
                        {
                            "type": STRING,
                            "class": STRING,
                            "href": STRING,
                            "fields": {
                                "type": "array",
                                "items": obj({"name": STRING, "type": STRING, "predicate": STRING}),
                            },
                        }
                    ),
                }
            }
        ),
        "Property": obj(
            {
                "type": STRING,
                "field": STRING,
                "datatype": STRING,
                "predicate": STRING,
                "collection": STRING,
                "href": STRING,
            }
        ),
        "Properties": obj({"items": {"type": "array", "items": ref("Property")}}),
        "Action": obj(
            {
                "name": STRING,
                "method": STRING,
                "target": STRING,
                "description": STRING,
                "consumes": NULLABLE_STRING,
                "href": STRING,
            }
        ),
        "Actions": obj({"items": {"type": "array", "items": ref("Action")}}),
    }
    for refinement in refinements:
        found[f"Refined_{refinement.name}"] = obj(
            {
                "id": INTEGER,
                "raw_id": INTEGER,
                "robot": STRING,
                "timestamp": NUMBER,
                **_fields(refinement.fields),
            }
        )
        found[f"Page_{refinement.name}"] = _page(f"Refined_{refinement.name}")
    return found


def _header(description: str, required: bool = True) -> dict[str, Any]:
    return {"description": description, "required": required, "schema": STRING}


PROBLEMS = {
    400: "invalid input, with the reasons",
    401: "missing or wrong bearer token",
    404: "no such resource",
    406: "neither text/turtle nor application/json is acceptable (Accept)",
    413: "the body is larger than the service takes (MAX_BODY)",
    426: "Upgrade: websocket without the WebSocket handshake",
    500: "server error",
}


def response(status: int, body: str | None, allow: str | None) -> dict[str, Any]:
    if status in (200, 201):
        content = {"text/turtle": {"schema": STRING}}
        if body is not None:
            content["application/json"] = {"schema": ref(body)}
        headers = {"ETag": _header("entity tag of the representation"), "Vary": _header("Accept")}
        if status == 201:
            headers["Location"] = _header("the created resource")
        return {
            "description": "Created"
            if status == 201
            else "the representation (Turtle unless Accept prefers JSON)",
            "headers": headers,
            "content": content,
        }
    if status == 204:
        answer: dict[str, Any] = {"description": "No Content"}
        if allow is not None:
            answer["headers"] = {"Allow": _header(f"the methods: {allow}")}
        return answer
    if status == 304:
        return {
            "description": "Not Modified (If-None-Match names the current ETag)",
            "headers": {"ETag": _header("entity tag of the representation")},
        }
    if status == 101:
        return {
            "description": "Switching Protocols: the WebSocket subscription (each new "
            "record as one text frame, JSON or Turtle as Accept asks)"
        }
    answer = {
        "description": PROBLEMS[status],
        "content": {"application/json": {"schema": ref("Problem")}},
    }
    if status == 401:
        answer["headers"] = {"WWW-Authenticate": _header("Bearer")}
    if status == 426:
        answer["headers"] = {"Upgrade": _header("websocket")}
    return answer


def openapi(
    app: FastAPI, store_schemas: dict[str, Any], token_env: str, protect_reads: bool
) -> dict[str, Any]:
    """The document of ``app``, made once: ``store_schemas`` (``schemas()``) as its
    components, the token (``token_env``) on the writes, and on every read when
    ``protect_reads``."""
    if app.openapi_schema:
        return app.openapi_schema
    document = get_openapi(
        title=app.title, version=app.version, description=app.description, routes=app.routes
    )
    components = document.setdefault("components", {})
    found = components.setdefault("schemas", {})
    for unused in ("HTTPValidationError", "ValidationError"):
        found.pop(unused, None)
    found.update(store_schemas)
    components["securitySchemes"] = {
        "bearer": {
            "type": "http",
            "scheme": "bearer",
            "description": f"the token the service was started with ({token_env})",
        }
    }
    for item in document["paths"].values():
        for operation in item.values():
            statuses = operation.pop(STATUSES)
            body = operation.pop(BODY, None)
            allow = operation.pop(ALLOW, None)
            token = operation.pop(TOKEN, False) or (protect_reads and 401 in statuses)
            parameters = [
                p
                for p in operation.get("parameters", [])
                if not (p["in"] == "header" and p["name"].lower() == "authorization")
            ]
            if parameters:
                operation["parameters"] = parameters
            else:
                operation.pop("parameters", None)
            operation["responses"] = {str(s): response(s, body, allow) for s in sorted(statuses)}
            if token:
                operation["security"] = [{"bearer": []}]
    app.openapi_schema = document
    return document
