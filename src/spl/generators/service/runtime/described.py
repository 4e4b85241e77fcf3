"""What a service says about itself (R1.8-R1.11): its subscriptions (bearer token), the
SHACL blueprint of its records, the fields of its data types as properties, and the
writes it offers as actions. The Turtle is the product's (linked.py); the JSON and the
routes are the same in every service.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

from fastapi import Depends, HTTPException, Path, Request
from fastapi.responses import Response

from .answers import Answers, related
from .reads import read_answers, subscription_answer, subscription_document
from .records import FieldSpec
from .routes import READ, Routes

if TYPE_CHECKING:
    from .service import StoreService

SUBSCRIPTION_ID = r"^[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}$"
SubscriptionId = Path(pattern=SUBSCRIPTION_ID, description="the subscription's id (a UUID)")
MANAGED = (200, 304, 401, 406, 500)


def data_types(service: StoreService) -> list[tuple[str, tuple[FieldSpec, ...]]]:
    """The store's data types and their fields: the raw type first, then the refined."""
    return [(service.raw_type, service.raw_fields)] + [
        (r.name, r.fields) for r in service.refinements
    ]


def property_document(
    model: str, property_path: str, type_name: str, field: FieldSpec, collection: str
) -> dict[str, Any]:
    """A field of a data type as JSON (``model``: the namespace of the model's terms)."""
    return {
        "type": type_name,
        "field": field.name,
        "datatype": field.type,
        "predicate": f"{model}{type_name}:{field.name}",
        "collection": collection,
        "href": property_path,
    }


def action_document(
    prefix: str, raw_type: str, name: str, action: tuple[str, str, str]
) -> dict[str, Any]:
    """An action (method, path under the store's ``prefix``, description) as JSON."""
    method, path, description = action
    return {
        "name": name,
        "method": method,
        "target": prefix + path,
        "description": description,
        "consumes": f"{prefix}/blueprint#{raw_type}" if method == "POST" else None,
        "href": f"{prefix}/actions/{name}",
    }


def choices(names: list[str]) -> Any:
    """A path parameter that can only name what exists (an enum in the OpenAPI
    document): ``Literal`` of ``names``, made when the product's names are known."""
    return Literal.__getitem__(tuple(names))


def add_routes(service: StoreService, routes: Routes, answers: Answers) -> None:
    """The subscriptions, blueprint, properties and actions of ``service``."""
    add_subscription_routes(service, routes, answers)
    prefix, linked, raw_type = service.prefix, service.linked, service.raw_type
    reader = [Depends(service.guard.reader)]
    reads = read_answers(service.settings)

    async def blueprint(request: Request) -> Response:
        document = {
            "shapes": [
                {
                    "type": name,
                    "class": linked.MODEL + name,
                    "href": f"{prefix}/blueprint#{name}",
                    "fields": [
                        {
                            "name": f.name,
                            "type": f.type,
                            "predicate": f"{linked.MODEL}{name}:{f.name}",
                        }
                        for f in fields
                    ],
                }
                for name, fields in data_types(service)
            ]
        }
        return answers.represent(request, document, linked.blueprint)

    routes.resource(
        prefix + "/blueprint",
        blueprint,
        "blueprint",
        reads,
        "SHACL shapes of the store's records (Turtle; the fields as JSON)",
        "Blueprint",
        dependencies=reader,
    )
    routes.options(prefix + "/blueprint", "blueprint", READ)

    found = {(t, f.name): (t, f, c) for t, f, c in linked.properties()}

    def document_of(type_name: str, field: FieldSpec, collection: str) -> dict[str, Any]:
        return property_document(
            linked.MODEL, linked.property_path(type_name, field.name), type_name, field, collection
        )

    async def list_properties(request: Request) -> Response:
        items = [document_of(*one) for one in found.values()]
        return answers.represent(
            request,
            {"items": items},
            linked.property_list,
            headers={"Link": related(*[i["href"] for i in items])},
        )

    async def get_property(request: Request, type_name: str, field: str) -> Response:
        one = found.get((type_name, field))
        if one is None:
            raise HTTPException(404, f"{type_name} has no field {field}")
        return answers.represent(
            request,
            document_of(*one),
            lambda links: linked.property_resource(links, *one),
            headers={"Link": related(one[2])},
        )

    get_property.__annotations__.update(
        type_name=choices([name for name, _ in data_types(service)]),
        field=choices(sorted({f for _, f in found})),
    )
    routes.resource(
        prefix + "/properties",
        list_properties,
        "properties",
        reads,
        "The fields of the store's data types (hybrit:Property)",
        "Properties",
        dependencies=reader,
    )
    routes.options(prefix + "/properties", "properties", READ)
    routes.resource(
        prefix + "/properties/{type_name}/{field}",
        get_property,
        "property",
        (*reads, 400, 404),
        "One field of a data type",
        "Property",
        dependencies=reader,
    )
    routes.options(prefix + "/properties/{type_name}/{field}", "property", READ)

    async def list_actions(request: Request) -> Response:
        items = [
            action_document(prefix, raw_type, name, linked.ACTIONS[name]) for name in linked.ACTIONS
        ]
        return answers.represent(
            request,
            {"items": items},
            linked.action_list,
            headers={"Link": related(*[i["href"] for i in items])},
        )

    async def get_action(request: Request, action: str) -> Response:
        return answers.represent(
            request,
            action_document(prefix, raw_type, action, linked.ACTIONS[action]),
            lambda links: linked.action_resource(links, action),
        )

    get_action.__annotations__["action"] = choices(list(linked.ACTIONS))
    routes.resource(
        prefix + "/actions",
        list_actions,
        "actions",
        reads,
        "The writes the store offers, with their shapes and HTTP bindings (hybrit:Action)",
        "Actions",
        dependencies=reader,
    )
    routes.options(prefix + "/actions", "actions", READ)
    routes.resource(
        prefix + "/actions/{action}",
        get_action,
        "action",
        (*reads, 400),
        "One action",
        "Action",
        dependencies=reader,
    )
    routes.options(prefix + "/actions/{action}", "action", READ)


def add_subscription_routes(service: StoreService, routes: Routes, answers: Answers) -> None:
    """The subscriptions as an LDP container: list, describe, cancel (bearer token)."""
    prefix, linked, check_token = service.prefix, service.linked, service.guard.check

    async def list_subscriptions(request: Request) -> Response:
        check_token(request.headers.get("authorization"))
        media = answers.media_of(request)
        items = await request.app.state.hub.describe_all()
        return answers.represent(
            request,
            {"items": [subscription_document(prefix, i) for i in items]},
            lambda links: linked.subscriptions(links, items),
            media=media,
            headers={"Link": related(*[f"{prefix}/subscriptions/{i['id']}" for i in items])}
            if items
            else None,
        )

    async def get_subscription(request: Request, subscription_id: str = SubscriptionId) -> Response:
        check_token(request.headers.get("authorization"))
        media = answers.media_of(request)
        item = await request.app.state.hub.describe(subscription_id)
        if item is None:
            raise HTTPException(404, f"no subscription {subscription_id}")
        return subscription_answer(service, answers, request, item, media=media)

    async def cancel_subscription(
        request: Request, subscription_id: str = SubscriptionId
    ) -> Response:
        check_token(request.headers.get("authorization"))
        if not await request.app.state.hub.cancel(subscription_id):
            raise HTTPException(404, f"no subscription {subscription_id}")
        return Response(status_code=204)

    path = prefix + "/subscriptions"
    routes.resource(
        path,
        list_subscriptions,
        "subscriptions",
        MANAGED,
        "The current subscriptions (an LDP container; bearer token)",
        "Subscriptions",
        token=True,
    )
    routes.options(path, "subscriptions", READ)
    routes.resource(
        path + "/{subscription_id}",
        get_subscription,
        "subscription",
        (*MANAGED, 400, 404),
        "One subscription (bearer token)",
        "Subscription",
        token=True,
    )
    routes.resource(
        path + "/{subscription_id}",
        cancel_subscription,
        "subscription",
        (204, 400, 401, 404, 500),
        "Cancel a subscription (bearer token)",
        methods=("DELETE",),
        status_code=204,
        token=True,
    )
    routes.options(path + "/{subscription_id}", "subscription", "GET, HEAD, DELETE, OPTIONS")
