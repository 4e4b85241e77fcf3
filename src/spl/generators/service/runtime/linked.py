"""A store as Linked Robotic Things (R1.1-R1.12 of "Requirements and Specifications for
Robots, Linked Data and all the REST", docs/services.md "Linked Robotic Things"): the
Turtle of every resource of a store, from the terms of turtle.py.

Vocabularies: SOSA/SSN for records (every record is a ``sosa:Observation`` made by its
robot, a ``sosa:Sensor``, at its ``sosa:resultTime``), Dublin Core terms, PROV (a
refined record ``prov:wasDerivedFrom`` its raw record), LDP containers, and the HybrIT
terms of the paper (``hybrit:subscriptions``, ``hybrit:property``, ``hybrit:action``,
``hybrit:blueprint``); the statements of the blueprint, properties and actions are
shapes.py's. The model's data types are classes of ``urn:spl:model:<System>:``
(``PositionInDEG``), their fields properties ``<Type>:<field>``; robots are
``urn:spl:robot:<System>:<robot id>`` (without ``<System>:`` when the model names no
system). Every name placed in Turtle is a validated identifier or an id, every text goes
through ``string()`` and every IRI through ``iri()``.

The store's names, data types and refinements are the product's: its generated
``linked.py`` passes them, with the process's content negotiation, to ``StoreDocuments``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from . import shapes
from .records import FieldSpec, Refinement
from .turtle import (
    Links,
    data_class,
    instant,
    iri,
    predicate,
    prefixes,
    statements,
    string,
    value,
)

# name: method, path under the store, description (the writes a store offers, R1.11)
ACTIONS = {
    "post-record": (
        "POST",
        "/records",
        "Store one raw record (JSON, bearer token); 201 + Location",
    ),
    "post-batch": (
        "POST",
        "/records/batch",
        "Store raw records in one all-or-nothing transaction (JSON, bearer token); 201",
    ),
    "cancel-subscription": (
        "DELETE",
        "/subscriptions/{id}",
        "Cancel a subscription (bearer token); 204",
    ),
}


class StoreDocuments:
    """The Turtle of one store's resources. ``system`` is the model's system name (None:
    a model without one, its types directly under ``urn:spl:model:``); ``negotiate`` is
    the content negotiation of the service's process, which remembers its choices."""

    ACTIONS = ACTIONS

    def __init__(
        self,
        store: str,
        system: str | None,
        prefix: str,
        raw_type: str,
        raw_fields: tuple[FieldSpec, ...],
        refinements: tuple[Refinement, ...],
        negotiate: Callable[[str | None], str],
    ) -> None:
        self.store_name, self.prefix = store, prefix
        self.raw_type, self.raw_fields, self.refinements = raw_type, raw_fields, refinements
        self.negotiate = negotiate
        self.MODEL = f"urn:spl:model:{system}:" if system else "urn:spl:model:"
        self.robots = f"urn:spl:robot:{system}:" if system else "urn:spl:robot:"
        self.prefixes = prefixes(self.MODEL)

    def iri(self, value: str) -> str:
        return iri(value)

    def robot_iri(self, robot: str) -> str:
        return iri(self.robots + robot)

    def document(self, *blocks: str) -> str:
        return self.prefixes + "\n".join(blocks)

    def one(self, statements_: str) -> str:
        return self.document(statements_)

    def properties(self) -> list[tuple[str, FieldSpec, str]]:
        """(data type, field, collection path) of every field of the store's data types."""
        prefix = self.prefix
        found = [(self.raw_type, f, f"{prefix}/records") for f in self.raw_fields]
        for refinement in self.refinements:
            found += [
                (refinement.name, f, f"{prefix}/{refinement.name}") for f in refinement.fields
            ]
        return found

    def property_path(self, type_name: str, field: str) -> str:
        return f"{self.prefix}/properties/{type_name}/{field}"

    def collections(self) -> list[str]:
        prefix = self.prefix
        return (
            [f"{prefix}/records"]
            + [f"{prefix}/{r.name}" for r in self.refinements]
            + [f"{prefix}/errors"]
        )

    def _thing(
        self, links: Links, subject_path: str, types: str, title: str, contains: list[str]
    ) -> str:
        prefix = self.prefix
        pairs: list[tuple[str, str | None]] = [("a", types), ("dcterms:title", string(title))]
        pairs += [("ldp:contains", links(p)) for p in contains]
        pairs += [
            ("hybrit:subscriptions", links(f"{prefix}/subscriptions")),
            ("hybrit:blueprint", links(f"{prefix}/blueprint")),
        ]
        pairs += [
            ("hybrit:property", links(self.property_path(t, f.name)))
            for t, f, _ in self.properties()
        ]
        pairs += [("hybrit:action", links(f"{prefix}/actions/{name}")) for name in self.ACTIONS]
        return statements(links(subject_path), pairs)

    def root(self, links: Links) -> str:
        return self.document(
            self._thing(
                links,
                "/",
                "hybrit:RoboticThing , ldp:BasicContainer",
                f"{self.store_name} data-acquisition service",
                [self.prefix],
            )
        )

    def store(self, links: Links) -> str:
        prefix = self.prefix
        blocks = [
            self._thing(
                links,
                prefix,
                "hybrit:RoboticThing , ldp:BasicContainer , spl:Store",
                f"{self.store_name} data-acquisition store",
                self.collections(),
            )
        ]
        collections = [(f"{prefix}/records", f"raw {self.raw_type} records", self.raw_type)]
        collections += [
            (f"{prefix}/{r.name}", f"refined {r.name} records", r.name) for r in self.refinements
        ]
        for path, title, type_name in collections:
            blocks.append(
                statements(
                    links(path),
                    [
                        ("a", "ldp:BasicContainer"),
                        ("dcterms:isPartOf", links(prefix)),
                        ("dcterms:title", string(title)),
                        ("spl:memberClass", data_class(type_name)),
                    ],
                )
            )
        blocks.append(
            statements(
                links(f"{prefix}/errors"),
                [
                    ("a", "ldp:BasicContainer"),
                    ("dcterms:isPartOf", links(prefix)),
                    ("spl:memberClass", "spl:TransformError"),
                ],
            )
        )
        return self.document(*blocks)

    def _robot(self, robot: str) -> str:
        return statements(
            self.robot_iri(robot), [("a", "sosa:Sensor"), ("dcterms:identifier", string(robot))]
        )

    def raw_record(self, links: Links, row: Any) -> str:
        """A raw record's statements (without prefixes)."""
        document_, prefix = row.document, self.prefix
        pairs: list[tuple[str, str | None]] = [
            ("a", f"sosa:Observation , {data_class(self.raw_type)}"),
            ("dcterms:identifier", str(int(row.id))),
            ("sosa:madeBySensor", self.robot_iri(row.robot)),
            ("sosa:resultTime", instant(row.source_ts)),
            ("dcterms:created", instant(row.received_ts)),
            ("dcterms:isPartOf", links(f"{prefix}/records")),
            ("spl:key", string(row.key) if row.key is not None else None),
        ]
        pairs += [
            (predicate(self.raw_type, f.name), value(f.type, document_[f.name]))
            for f in self.raw_fields
            if f.name in document_
        ]
        subject = links(f"{prefix}/records/{int(row.id)}")
        return statements(subject, pairs) + self._robot(row.robot)

    def refined_record(self, links: Links, refinement: Refinement, row: Any) -> str:
        mapping, prefix = row._mapping, self.prefix
        pairs: list[tuple[str, str | None]] = [
            ("a", f"sosa:Observation , {data_class(refinement.name)}"),
            ("dcterms:identifier", str(int(row.id))),
            ("sosa:madeBySensor", self.robot_iri(row.robot)),
            ("sosa:resultTime", instant(row.timestamp)),
            ("prov:wasDerivedFrom", links(f"{prefix}/records/{int(row.raw_id)}")),
            ("dcterms:isPartOf", links(f"{prefix}/{refinement.name}")),
        ]
        pairs += [
            (predicate(refinement.name, f.name), value(f.type, mapping[f.name]))
            for f in refinement.fields
        ]
        subject = links(f"{prefix}/{refinement.name}/{int(row.id)}")
        return statements(subject, pairs) + self._robot(row.robot)

    def error_record(self, links: Links, row: Any) -> str:
        prefix = self.prefix
        return statements(
            iri(links.url(f"{prefix}/errors") + f"#e{int(row.id)}"),
            [
                ("a", "spl:TransformError"),
                ("dcterms:identifier", str(int(row.id))),
                ("spl:refinement", string(row.refinement)),
                ("spl:rawRecord", links(f"{prefix}/records/{int(row.raw_id)}")),
                ("spl:message", string(row.message)),
            ],
        )

    def page(
        self,
        links: Links,
        path: str,
        url: str,
        member_paths: list[str],
        blocks: list[str],
        next_url: str | None,
    ) -> str:
        """A page of a collection: the collection contains the members described here."""
        head = [("a", "ldp:BasicContainer"), ("dcterms:isPartOf", links(self.prefix))]
        head += [("ldp:contains", m) for m in member_paths]
        parts = [statements(links(path), head)]
        if next_url is not None:
            parts.append(statements(iri(url), [("xhv:next", iri(next_url))]))
        return self.document(*parts, *blocks)

    def created(self, links: Links, paths: list[str], batch: bool) -> str:
        """The answer to a post: the records collection contains the new (or already
        stored) records; a batch also lists them in the order they were posted."""
        pairs = [("ldp:contains", links(p)) for p in dict.fromkeys(paths)]
        parts = [statements(links(f"{self.prefix}/records"), pairs)]
        if batch:
            members = " ".join(links(p) for p in paths)
            parts.append(
                statements(
                    links(f"{self.prefix}/records/batch"), [("spl:stored", f"( {members} )")]
                )
            )
        return self.document(*parts)

    def subscription(self, links: Links, item: dict[str, Any]) -> str:
        kind = "hybrit:WebCallback" if item["type"] == "callback" else "hybrit:WebSocket"
        callback = item.get("callback")
        return statements(
            links(f"{self.prefix}/subscriptions/{item['id']}"),
            [
                ("a", f"hybrit:Subscription , {kind}"),
                ("dcterms:identifier", string(item["id"])),
                ("hybrit:onResource", links(item["resource"])),
                ("hybrit:callbackURL", string(callback) + "^^xsd:anyURI" if callback else None),
                ("hybrit:mediaType", string(item["media_type"])),
                ("dcterms:created", instant(item["created"])),
            ],
        )

    def subscriptions(self, links: Links, items: list[dict[str, Any]]) -> str:
        path = f"{self.prefix}/subscriptions"
        head = [
            ("a", "ldp:BasicContainer , ldp:Container"),
            ("dcterms:isPartOf", links(self.prefix)),
            ("dcterms:title", string(f"subscriptions to the collections of {self.store_name}")),
        ]
        head += [("ldp:contains", links(f"{path}/{item['id']}")) for item in items]
        return self.document(
            statements(links(path), head), *[self.subscription(links, item) for item in items]
        )

    # the blueprint, properties and actions: shapes.py

    def blueprint(self, links: Links) -> str:
        return self.document(*shapes.blueprint(self, links))

    def property_list(self, links: Links) -> str:
        path, found = f"{self.prefix}/properties", self.properties()
        head = [("a", "ldp:BasicContainer"), ("dcterms:isPartOf", links(self.prefix))]
        head += [("ldp:contains", links(self.property_path(t, f.name))) for t, f, _ in found]
        return self.document(
            statements(links(path), head),
            *[shapes.property_statements(self, links, t, f, c) for t, f, c in found],
        )

    def property_resource(
        self, links: Links, type_name: str, field: FieldSpec, collection: str
    ) -> str:
        return self.document(shapes.property_statements(self, links, type_name, field, collection))

    def action_list(self, links: Links) -> str:
        path = f"{self.prefix}/actions"
        head = [("a", "ldp:BasicContainer"), ("dcterms:isPartOf", links(self.prefix))]
        head += [("ldp:contains", links(f"{path}/{name}")) for name in self.ACTIONS]
        return self.document(
            statements(links(path), head),
            *[shapes.action_statements(self, links, n) for n in self.ACTIONS],
        )

    def action_resource(self, links: Links, name: str) -> str:
        return self.document(shapes.action_statements(self, links, name))
