"""The Turtle of a store's resources (the runtime's StoreDocuments, which every
generated service's linked.py fills with its store's names and data types), imported
directly (docs/services.md, "Linked Robotic Things"): each document parsed by rdflib,
as the live tests (tests/live/test_service_linked.py) parse a running service's."""

from __future__ import annotations

from types import SimpleNamespace

import rdflib
from rdflib.namespace import DCTERMS, RDF, RDFS, SH, XSD

from spl.generators.service.runtime.linked import ACTIONS, StoreDocuments
from spl.generators.service.runtime.records import KEY_PATTERN, FieldSpec, Refinement
from spl.generators.service.runtime.turtle import Links, Negotiation

BASE = "http://shop.example:8000"
LINKS = Links(BASE + "/")
MODEL = rdflib.Namespace("urn:spl:model:Shop:")
LDP = rdflib.Namespace("http://www.w3.org/ns/ldp#")
SOSA = rdflib.Namespace("http://www.w3.org/ns/sosa/")
PROV = rdflib.Namespace("http://www.w3.org/ns/prov#")
HYBRIT = rdflib.Namespace("https://hybr-it-projekt.de/ns/hybr-it#")
SPL = rdflib.Namespace("urn:spl:vocab:")
HTTP = rdflib.Namespace("http://www.w3.org/2011/http#")


def documents(system: str | None = "Shop") -> StoreDocuments:
    refined = Refinement(
        name="Total",
        table=None,
        fields=(FieldSpec("sum", "double"),),
        transform=None,
        period=1.0,
        uses_prev=False,
        uses_next=False,
    )
    return StoreDocuments(
        store="Sales",
        system=system,
        prefix="/Sales",
        raw_type="Sale",
        raw_fields=(FieldSpec("price", "double"), FieldSpec("note", "string")),
        refinements=(refined,),
        negotiate=Negotiation().negotiate,
    )


def url(path: str) -> rdflib.URIRef:
    return rdflib.URIRef(BASE + path)


def graph(text: str) -> rdflib.Graph:
    return rdflib.Graph().parse(data=text, format="turtle")


def test_the_store_contains_its_collections_each_of_its_data_type() -> None:
    store = graph(documents().store(LINKS))
    assert set(store.objects(url("/Sales"), LDP.contains)) == {
        url("/Sales/records"),
        url("/Sales/Total"),
        url("/Sales/errors"),
    }
    assert (url("/Sales"), RDF.type, SPL.Store) in store
    assert store.value(url("/Sales/records"), SPL.memberClass) == MODEL.Sale
    assert store.value(url("/Sales/Total"), SPL.memberClass) == MODEL.Total
    assert store.value(url("/Sales/errors"), SPL.memberClass) == SPL.TransformError
    assert set(store.objects(url("/Sales"), HYBRIT.property)) == {
        url("/Sales/properties/Sale/price"),
        url("/Sales/properties/Sale/note"),
        url("/Sales/properties/Total/sum"),
    }
    assert len(set(store.objects(url("/Sales"), HYBRIT.action))) == len(ACTIONS) == 3
    root = graph(documents().root(LINKS))
    assert set(root.objects(url("/"), LDP.contains)) == {url("/Sales")}
    assert str(root.value(url("/"), DCTERMS.title)) == "Sales data-acquisition service"


def test_records_are_observations_of_their_robot_and_refined_ones_name_their_origin() -> None:
    raw = SimpleNamespace(
        id=7,
        robot="r1",
        source_ts=1.5,
        received_ts=2.0,
        key=None,
        document={"price": 2.5, "note": 'a "quoted" > note'},
    )
    found = graph(documents().one(documents().raw_record(LINKS, raw)))
    record = url("/Sales/records/7")
    assert set(found.objects(record, RDF.type)) == {SOSA.Observation, MODEL.Sale}
    assert found.value(record, rdflib.URIRef(MODEL + "Sale:note")).toPython() == (
        'a "quoted" > note'
    )
    assert found.value(record, SPL.key) is None  # a record posted without a key
    robot = rdflib.URIRef("urn:spl:robot:Shop:r1")
    assert found.value(record, SOSA.madeBySensor) == robot
    assert (robot, RDF.type, SOSA.Sensor) in found
    refined = SimpleNamespace(id=3, raw_id=7, robot="r1", timestamp=1.5, _mapping={"sum": 4.0})
    total = documents().refinements[0]
    found = graph(documents().one(documents().refined_record(LINKS, total, refined)))
    assert found.value(url("/Sales/Total/3"), PROV.wasDerivedFrom) == record
    assert found.value(url("/Sales/Total/3"), rdflib.URIRef(MODEL + "Total:sum")).toPython() == 4.0


def test_a_model_without_a_system_name_puts_its_terms_directly_under_the_model() -> None:
    plain = documents(system=None)
    assert plain.MODEL == "urn:spl:model:"
    assert plain.robot_iri("r1") == "<urn:spl:robot:r1>"
    store = graph(plain.store(LINKS))
    assert store.value(url("/Sales/records"), SPL.memberClass) == rdflib.URIRef(
        "urn:spl:model:Sale"
    )


def test_the_blueprint_shapes_raw_and_refined_records_differently() -> None:
    shapes = graph(documents().blueprint(LINKS))
    raw, total = url("/Sales/blueprint#Sale"), url("/Sales/blueprint#Total")

    def paths(shape: rdflib.URIRef) -> dict[rdflib.term.Node, rdflib.term.Node]:
        return {shapes.value(p, SH.path): p for p in shapes.objects(shape, SH.property)}

    assert shapes.value(raw, SH.targetClass) == MODEL.Sale
    raw_paths, total_paths = paths(raw), paths(total)
    assert SPL.key in raw_paths and PROV.wasDerivedFrom not in raw_paths
    assert str(shapes.value(raw_paths[SPL.key], SH.pattern)) == KEY_PATTERN
    assert PROV.wasDerivedFrom in total_paths and SPL.key not in total_paths
    price = raw_paths[rdflib.URIRef(MODEL + "Sale:price")]
    assert shapes.value(price, SH.datatype) == XSD.double
    for resource in ("Robot", "TransformError", "Subscription", "WebCallback"):
        assert (url(f"/Sales/blueprint#{resource}"), RDF.type, SH.NodeShape) in shapes


def test_properties_and_actions_describe_themselves_and_their_requests() -> None:
    one = graph(
        documents().property_resource(LINKS, "Sale", FieldSpec("price", "double"), "/Sales/records")
    )
    term = rdflib.URIRef(MODEL + "Sale:price")
    assert one.value(url("/Sales/properties/Sale/price"), DCTERMS.subject) == term
    assert one.value(term, RDFS.range) == XSD.double and one.value(term, RDFS.domain) == MODEL.Sale
    listed = graph(documents().property_list(LINKS))
    assert len(set(listed.objects(url("/Sales/properties"), LDP.contains))) == 3
    actions = graph(documents().action_list(LINKS))
    post = actions.value(url("/Sales/actions/post-record"), HYBRIT.binding)
    assert actions.value(post, HTTP.requestURI) == url("/Sales/records")
    assert actions.value(url("/Sales/actions/post-record"), HYBRIT.consumes) == url(
        "/Sales/blueprint#Sale"
    )
    cancel = graph(documents().action_resource(LINKS, "cancel-subscription"))
    binding = cancel.value(url("/Sales/actions/cancel-subscription"), HYBRIT.binding)
    # a path with a parameter is a URI template: a literal, not an IRI
    uri = cancel.value(binding, HTTP.requestURI)
    assert isinstance(uri, rdflib.Literal) and str(uri) == BASE + "/Sales/subscriptions/{id}"
    assert cancel.value(url("/Sales/actions/cancel-subscription"), HYBRIT.consumes) is None


def test_pages_posts_and_subscriptions_name_their_members() -> None:
    page = graph(
        documents().page(LINKS, "/Sales/records", BASE + "/Sales/records", [], [], BASE + "/n")
    )
    assert page.value(
        url("/Sales/records"), rdflib.URIRef("http://www.w3.org/1999/xhtml/vocab#next")
    ) == url("/n")
    created = documents().created(LINKS, ["/Sales/records/1", "/Sales/records/1"], batch=True)
    found = graph(created)
    assert set(found.objects(url("/Sales/records"), LDP.contains)) == {url("/Sales/records/1")}
    stored = rdflib.collection.Collection(
        found, found.value(url("/Sales/records/batch"), SPL.stored)
    )
    assert list(stored) == [url("/Sales/records/1"), url("/Sales/records/1")]
    item = {
        "type": "callback",
        "id": "abc",
        "resource": "/Sales/records",
        "callback": "https://hook.example/x",
        "media_type": "application/json",
        "created": 10.0,
    }
    subscriptions = graph(documents().subscriptions(LINKS, [item]))
    subscription = url("/Sales/subscriptions/abc")
    assert (subscription, RDF.type, HYBRIT.WebCallback) in subscriptions
    callback = subscriptions.value(subscription, HYBRIT.callbackURL)
    assert callback.datatype == XSD.anyURI and str(callback) == "https://hook.example/x"
    assert subscriptions.value(subscription, HYBRIT.onResource) == url("/Sales/records")
