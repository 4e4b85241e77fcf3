"""The generated services as Linked Robotic Things (R1.1-R1.12 of the Linked Data
requirements, docs/services.md): Turtle unless
the Accept header prefers JSON (406 when neither fits), an rdf:type on every record
(SOSA observations of the model's data types), the root and the store linking their
subscriptions, properties, actions and SHACL blueprint with the hybrit: terms, and
every record's own Turtle satisfying the blueprint (checked with pyshacl). Texts of any
kind survive the Turtle (parsed back with rdflib)."""

from __future__ import annotations

import http.client
import json
import urllib.error
import urllib.request
from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st
from pyshacl import validate
from rdflib import RDF, Graph, Literal, Namespace, URIRef, namespace

from spl.dsl.tsm import language as tsm_language
from spl.generators.service import generator as service
from spl.resolver.architecture.product import ResolvedProduct

from support.hypothesis_budget import examples
from support.service_models import product
from support.service_runtime import TOKEN, RunningService, request, wait_for, write_files

HYBRIT = Namespace("https://hybr-it-projekt.de/ns/hybr-it#")
SOSA = Namespace("http://www.w3.org/ns/sosa/")
LDP = Namespace("http://www.w3.org/ns/ldp#")
HTTP = Namespace("http://www.w3.org/2011/http#")
NOTES = Namespace("urn:spl:model:Notes:")
DATA = Namespace("urn:spl:model:DataAcquisition:")

NOTES_TSM = """system Notes
data Note {
    text : string
    count : int
    ok : bool
    value : double
}
data Tagged {
    text : string
    count : int
    ok : bool
    value : double
}
transform Tag : Note -> Tagged {
    text = text
    count = count + 1
    ok = ok
    value = value * 2.0
}
cloud container Cloud {
    store NoteStore {
        raw Note
        refined Tagged by Tag every 1 s
    }
}
"""


def _start(root: Path, store: str, slug: str, **env: str) -> RunningService:
    environment = {
        f"{slug.upper()}_TOKEN": TOKEN,
        f"{slug.upper()}_TRANSFORM_PERIOD": "0.05",
        **env,
    }
    return RunningService(root / "services" / store, f"{slug}_service", environment).start()


@pytest.fixture(scope="module")
def notes(tmp_path_factory: pytest.TempPathFactory):  # type: ignore[no-untyped-def]
    system = tsm_language.parse_text(NOTES_TSM, "notes.tsm")
    root = write_files(
        service.generate(ResolvedProduct("notes", system, ())), tmp_path_factory.mktemp("notes")
    )
    running = _start(root, "NoteStore", "note_store")
    yield running
    running.stop()


@pytest.fixture(scope="module")
def positions(tmp_path_factory: pytest.TempPathFactory):  # type: ignore[no-untyped-def]
    root = write_files(service.generate(product()), tmp_path_factory.mktemp("linked"))
    running = _start(root, "PositionStore", "position_store")
    yield running
    running.stop()


def fetch(
    url: str,
    accept: str | None = None,
    token: str | None = TOKEN,
) -> tuple[int, dict[str, str], bytes]:
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    if accept is not None:
        headers["Accept"] = accept
    try:
        with urllib.request.urlopen(
            urllib.request.Request(url, headers=headers), timeout=30
        ) as answer:
            return answer.status, {k.lower(): v for k, v in answer.headers.items()}, answer.read()
    except urllib.error.HTTPError as error:
        return error.code, {k.lower(): v for k, v in error.headers.items()}, error.read()


def graph(url: str, token: str | None = TOKEN) -> Graph:
    """The resource's Turtle (asked for with no Accept header at all: Turtle is the
    default), parsed."""
    status, headers, body = fetch(url, token=token)
    assert status == 200, body
    assert headers["content-type"] == "text/turtle; charset=utf-8"
    return Graph().parse(data=body.decode(), format="turtle")


def post_notes(base: str, records: list[dict]) -> list[int]:
    status, _, body = request("POST", f"{base}/records/batch", {"records": records})
    assert status == 201, body
    return body["ids"]


def note(
    text: str, count: int = 1, ok: bool = True, value: float = 1.5, timestamp: float = 1.7e9
) -> dict:
    return {
        "robot": "scribe",
        "timestamp": timestamp,
        "data": {"text": text, "count": count, "ok": ok, "value": value},
    }


def test_turtle_is_the_default_and_accept_chooses(positions) -> None:
    base = f"{positions.url}/PositionStore"
    status, _, body = request(
        "POST",
        f"{base}/records",
        {"robot": "r", "timestamp": 10.0, "data": {"lat": 1.0, "lon": 2.0}},
    )
    url = f"{positions.url}{body['href']}"
    for accept, expected in [
        (None, "text/turtle"),
        ("*/*", "text/turtle"),
        ("text/turtle", "text/turtle"),
        ("text/*", "text/turtle"),
        ("application/json", "application/json"),
        ("application/*", "application/json"),
        ("application/json, */*", "application/json"),  # named beats the wildcard
        ("text/turtle;q=0.5, application/json", "application/json"),
        ("application/json;q=0.4, text/turtle;q=0.9", "text/turtle"),
        ("text/html, application/json;q=0.1", "application/json"),
    ]:
        status, headers, body = fetch(url, accept)
        assert status == 200, (accept, body)
        assert headers["content-type"].split(";")[0] == expected, accept
        assert headers["vary"] == "Accept" and headers["etag"]
    for accept in ("text/html", "application/xml, image/*", "application/json;q=0, text/x"):
        status, headers, body = fetch(url, accept)
        assert status == 406, accept
        answer = json.loads(body)
        assert answer["status"] == 406 and "text/turtle or application/json" in answer["detail"]
    # each representation has an ETag of its own; a GET with it gets 304
    _, json_headers, _ = fetch(url, "application/json")
    _, turtle_headers, _ = fetch(url, "text/turtle")
    assert json_headers["etag"] != turtle_headers["etag"]
    request_ = urllib.request.Request(url, headers={"If-None-Match": turtle_headers["etag"]})
    with pytest.raises(urllib.error.HTTPError) as not_modified:
        urllib.request.urlopen(request_, timeout=10)
    assert not_modified.value.code == 304
    # a post's answer is negotiated too: an unacceptable one stores nothing
    before = request("GET", f"{base}/records?robot=refused")[2]["items"]
    status, _, _ = request(
        "POST",
        f"{base}/records",
        {"robot": "refused", "timestamp": 1.0, "data": {"lat": 1.0, "lon": 2.0}},
        headers={"Accept": "text/html"},
    )
    assert status == 406
    assert request("GET", f"{base}/records?robot=refused")[2]["items"] == before == []


def test_records_are_typed_observations_that_satisfy_the_blueprint(notes) -> None:
    base = f"{notes.url}/NoteStore"
    ids = post_notes(
        base,
        [
            note('quote " and \\ backslash\nnew line\r\ttab', count=-(2**63)),
            note("ünïcödé ✓ 🤖", count=2**63 - 1, ok=False, value=-0.0),
            note("", value=1e-300),
        ],
    )
    shapes = graph(f"{base}/blueprint")
    assert {(s, o) for s, o in shapes.subject_objects(namespace.SH.targetClass)} >= {
        (URIRef(f"{base}/blueprint#Note"), NOTES.Note),
        (URIRef(f"{base}/blueprint#Tagged"), NOTES.Tagged),
    }
    refined = wait_for(lambda: request("GET", f"{base}/Tagged?robot=scribe")[2]["items"])
    documents = [
        f"{base}/records/{ids[0]}",
        f"{base}/records",
        f"{base}/Tagged",
        f"{base}/Tagged/{refined[0]['id']}",
        f"{base}/errors",
    ]
    for url in documents:
        data = graph(url)
        conforms, _, report = validate(data, shacl_graph=shapes)
        assert conforms, (url, report)
    one = graph(f"{base}/records/{ids[0]}")
    record = URIRef(f"{base}/records/{ids[0]}")
    assert set(one.objects(record, RDF.type)) == {SOSA.Observation, NOTES.Note}
    assert one.value(record, NOTES["Note:text"]) == Literal(
        'quote " and \\ backslash\nnew line\r\ttab'
    )
    assert one.value(record, NOTES["Note:count"]).toPython() == -(2**63)
    robot = one.value(record, SOSA.madeBySensor)
    assert (robot, RDF.type, SOSA.Sensor) in one
    assert one.value(robot, namespace.DCTERMS.identifier) == Literal("scribe")
    assert one.value(record, SOSA.resultTime).datatype == namespace.XSD.dateTime
    derived = graph(f"{base}/Tagged/{refined[0]['id']}")
    refined_iri = URIRef(f"{base}/Tagged/{refined[0]['id']}")
    assert set(derived.objects(refined_iri, RDF.type)) == {SOSA.Observation, NOTES.Tagged}
    assert derived.value(refined_iri, URIRef("http://www.w3.org/ns/prov#wasDerivedFrom")) == URIRef(
        f"{base}/records/{refined[0]['raw_id']}"
    )
    # the shapes have teeth: a record missing its time or with a text count fails them
    broken = Graph().parse(data=one.serialize(format="turtle"), format="turtle")
    broken.remove((record, SOSA.resultTime, None))
    assert not validate(broken, shacl_graph=shapes)[0]
    broken = Graph().parse(data=one.serialize(format="turtle"), format="turtle")
    broken.set((record, NOTES["Note:count"], Literal("many")))
    assert not validate(broken, shacl_graph=shapes)[0]


@settings(max_examples=examples(25))
@given(
    st.text(st.characters(blacklist_categories=("Cs",), blacklist_characters="\x00"), max_size=40)
)
def test_any_text_comes_back_from_the_turtle(notes, text: str) -> None:
    base = f"{notes.url}/NoteStore"
    (record_id,) = post_notes(base, [note(text)])
    data = graph(f"{base}/records/{record_id}")
    assert data.value(URIRef(f"{base}/records/{record_id}"), NOTES["Note:text"]) == Literal(text)


def test_root_and_store_link_their_sub_resources_with_hybrit_terms(positions) -> None:
    base = f"{positions.url}/PositionStore"
    for subject, url in [(URIRef(f"{positions.url}/"), f"{positions.url}/"), (URIRef(base), base)]:
        data = graph(url)
        assert (subject, RDF.type, HYBRIT.RoboticThing) in data
        (subscriptions,) = data.objects(subject, HYBRIT.subscriptions)
        (blueprint,) = data.objects(subject, HYBRIT.blueprint)
        properties = set(data.objects(subject, HYBRIT.property))
        actions = set(data.objects(subject, HYBRIT.action))
        assert subscriptions == URIRef(f"{base}/subscriptions")
        assert len(properties) == 4 and len(actions) == 3
    container = graph(str(subscriptions))
    assert (subscriptions, RDF.type, LDP.Container) in container
    shapes = graph(str(blueprint))
    assert set(shapes.objects(None, namespace.SH.targetClass)) >= {
        DATA.PositionInSecond,
        DATA.PositionInDEG,
    }
    for iri in properties:
        data = graph(str(iri))
        assert (iri, RDF.type, HYBRIT.Property) in data
        term = data.value(iri, namespace.DCTERMS.subject)
        assert str(term).startswith(str(DATA)) and data.value(term, RDF.type) == RDF.Property
    for iri in actions:
        data = graph(str(iri))
        assert (iri, RDF.type, HYBRIT.Action) in data
        binding = data.value(iri, HYBRIT.binding)
        assert data.value(binding, RDF.type) == HTTP.Request
        assert data.value(binding, HTTP.mthd) is not None
    post = URIRef(f"{base}/actions/post-record")
    data = graph(str(post))
    assert data.value(data.value(post, HYBRIT.binding), HTTP.requestURI) == URIRef(
        f"{base}/records"
    )
    assert data.value(post, HYBRIT.consumes) == URIRef(f"{base}/blueprint#PositionInSecond")
    # the JSON of the store names them too
    store = request("GET", base)[2]
    assert store["subscriptions"]["href"] == "/PositionStore/subscriptions"
    status, _, answer = request("GET", f"{base}/properties/PositionInDEG/nothing")
    assert status == 400  # not a field of any type: refused by the path's enum
    status, _, answer = request("GET", f"{base}/properties/PositionInDEG/lat")
    assert (
        status == 200 and answer["predicate"] == "urn:spl:model:DataAcquisition:PositionInDEG:lat"
    )


def test_a_hostile_host_header_cannot_break_the_turtle(positions) -> None:
    for host in ('evil"> <urn:x> <urn:y', "a{b}|c^d`e\\f", "x\x7fy"):
        connection = http.client.HTTPConnection("127.0.0.1", positions.port, timeout=10)
        connection.putrequest("GET", "/PositionStore", skip_host=True)
        connection.putheader("Host", host)
        connection.endheaders()
        answer = connection.getresponse()
        body = answer.read().decode()
        connection.close()
        if answer.status == 400:  # refused by the HTTP parser
            continue
        assert answer.status == 200
        data = Graph().parse(data=body, format="turtle")  # parses: IRIs were escaped
        assert len(data) > 10
