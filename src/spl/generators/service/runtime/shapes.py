"""What a store says about its records in Turtle (R1.8-R1.11, docs/services.md "Linked
Robotic Things"): the SHACL blueprint of its records, robots, transform errors and
subscriptions, each field of its data types as a ``hybrit:Property``, and each write it
offers as a ``hybrit:Action`` bound to its HTTP request (the W3C HTTP vocabulary).
linked.py puts these statements in its documents.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .records import KEY_PATTERN, FieldSpec
from .turtle import DATATYPES, JSON, TURTLE, Links, data_class, iri, predicate, statements, string

if TYPE_CHECKING:
    from .linked import StoreDocuments

ONE = (("sh:minCount", "1"), ("sh:maxCount", "1"))
ROBOT_ID = r"^[A-Za-z0-9_.\-]{1,64}$"  # the robot ids a post accepts (model.py)


def shape_property(path: str, *constraints: tuple[str, str]) -> str:
    """A ``sh:property`` node: the path and its constraints, as a blank node."""
    inner = " ; ".join(f"{p} {o}" for p, o in [("sh:path", path), *constraints])
    return f"[ {inner} ]"


def record_shape(
    documents: StoreDocuments,
    links: Links,
    type_name: str,
    fields: tuple[FieldSpec, ...],
    raw: bool,
) -> str:
    """The shape of a raw record (its arrival and key) or of a refined one (its origin)."""
    shape = iri(links.url(f"{documents.prefix}/blueprint") + f"#{type_name}")
    shapes = [
        shape_property("dcterms:identifier", *ONE, ("sh:datatype", "xsd:integer")),
        shape_property(
            "sosa:madeBySensor", *ONE, ("sh:nodeKind", "sh:IRI"), ("sh:class", "sosa:Sensor")
        ),
        shape_property("sosa:resultTime", *ONE, ("sh:datatype", "xsd:dateTime")),
        shape_property("dcterms:isPartOf", *ONE, ("sh:nodeKind", "sh:IRI")),
    ]
    if raw:
        shapes += [
            shape_property("dcterms:created", *ONE, ("sh:datatype", "xsd:dateTime")),
            shape_property(
                "spl:key",
                ("sh:maxCount", "1"),
                ("sh:datatype", "xsd:string"),
                ("sh:pattern", string(KEY_PATTERN)),
            ),
        ]
    else:
        shapes.append(shape_property("prov:wasDerivedFrom", *ONE, ("sh:nodeKind", "sh:IRI")))
    shapes += [
        shape_property(
            predicate(type_name, f.name),
            *ONE,
            ("sh:datatype", DATATYPES[f.type]),
            ("sh:name", string(f.name)),
        )
        for f in fields
    ]
    return statements(
        shape,
        [
            ("a", "sh:NodeShape"),
            ("sh:targetClass", data_class(type_name)),
            ("rdfs:label", string(type_name)),
            ("sh:closed", "false"),
            *[("sh:property", s) for s in shapes],
        ],
    )


def node_shape(subject: str, target: str, *properties: str) -> str:
    return statements(
        subject,
        [("a", "sh:NodeShape"), ("sh:targetClass", target)]
        + [("sh:property", p) for p in properties],
    )


def blueprint(documents: StoreDocuments, links: Links) -> list[str]:
    """The blueprint's statements: itself, then a shape per data type and resource."""
    prefix = documents.prefix
    base = links.url(f"{prefix}/blueprint")
    title = f"SHACL shapes of the resources of {documents.store_name}"
    blocks = [
        statements(
            links(f"{prefix}/blueprint"),
            [
                ("a", "hybrit:Blueprint"),
                ("dcterms:title", string(title)),
                ("rdfs:seeAlso", links(prefix)),
            ],
        ),
        record_shape(documents, links, documents.raw_type, documents.raw_fields, raw=True),
    ]
    blocks += [
        record_shape(documents, links, r.name, r.fields, raw=False) for r in documents.refinements
    ]
    string_ = ("sh:datatype", "xsd:string")
    blocks.append(
        node_shape(
            iri(base + "#Robot"),
            "sosa:Sensor",
            shape_property("dcterms:identifier", *ONE, string_, ("sh:pattern", string(ROBOT_ID))),
        )
    )
    blocks.append(
        node_shape(
            iri(base + "#TransformError"),
            "spl:TransformError",
            shape_property("dcterms:identifier", *ONE, ("sh:datatype", "xsd:integer")),
            shape_property("spl:refinement", *ONE, string_),
            shape_property("spl:rawRecord", *ONE, ("sh:nodeKind", "sh:IRI")),
            shape_property("spl:message", *ONE, string_),
        )
    )
    media = ("sh:in", f"( {string(TURTLE)} {string(JSON)} )")
    blocks.append(
        node_shape(
            iri(base + "#Subscription"),
            "hybrit:Subscription",
            shape_property("dcterms:identifier", *ONE, string_),
            shape_property("hybrit:onResource", *ONE, ("sh:nodeKind", "sh:IRI")),
            shape_property("hybrit:mediaType", *ONE, media),
        )
    )
    blocks.append(
        node_shape(
            iri(base + "#WebCallback"),
            "hybrit:WebCallback",
            shape_property("hybrit:callbackURL", *ONE, ("sh:datatype", "xsd:anyURI")),
        )
    )
    return blocks


def property_statements(
    documents: StoreDocuments, links: Links, type_name: str, field: FieldSpec, collection: str
) -> str:
    """A field as a resource of the store, and the RDF property of its values."""
    term = predicate(type_name, field.name)
    resource = statements(
        links(documents.property_path(type_name, field.name)),
        [
            ("a", "hybrit:Property"),
            ("dcterms:identifier", string(f"{type_name}.{field.name}")),
            ("rdfs:label", string(field.name)),
            ("dcterms:subject", term),
            ("rdfs:seeAlso", links(collection)),
        ],
    )
    return resource + statements(
        term,
        [
            ("a", "rdf:Property"),
            ("rdfs:label", string(field.name)),
            ("rdfs:domain", data_class(type_name)),
            ("rdfs:range", DATATYPES[field.type]),
        ],
    )


def action_statements(documents: StoreDocuments, links: Links, name: str) -> str:
    """An action and the HTTP request that performs it; a post consumes and produces a
    raw record, and a path with a ``{parameter}`` is a template, not an IRI."""
    method, path, description = documents.ACTIONS[name]
    prefix = documents.prefix
    shape = iri(links.url(f"{prefix}/blueprint") + f"#{documents.raw_type}")
    if "{" in path:
        target = ("http:requestURI", string(links.url(prefix + path)))
    else:
        target = ("http:requestURI", links(prefix + path))
    binding = [("a", "http:Request"), ("http:mthd", f"htm:{method}"), target]
    if method == "POST":
        binding.append(
            (
                "http:headers",
                '( [ a http:RequestHeader ; http:fieldName "Content-Type" ; '
                'http:fieldValue "application/json" ] )',
            )
        )
    inner = " ; ".join(f"{p} {o}" for p, o in binding)
    pairs = [
        ("a", "hybrit:Action"),
        ("dcterms:identifier", string(name)),
        ("dcterms:description", string(description)),
        ("hybrit:consumes", shape if method == "POST" else None),
        ("hybrit:produces", shape if method == "POST" else None),
        ("hybrit:binding", f"[ {inner} ]"),
        ("rdfs:seeAlso", links("/openapi.json")),
    ]
    return statements(links(f"{prefix}/actions/{name}"), pairs)
