"""The runtime's Linked Data terms and content negotiation, imported directly
(docs/services.md, "Linked Data"): Turtle unless the Accept header prefers JSON, 406
when neither is acceptable; every text and IRI escaped so that a hostile value cannot
leave its term; numbers and instants typed as XSD. The documents are parsed by rdflib,
the parser the live tests (tests/live/test_service_linked.py) use on running services."""

from __future__ import annotations

import datetime
import math

import pytest
import rdflib

from spl.generators.service.runtime.turtle import (
    Links,
    Negotiation,
    NotAcceptable,
    choose,
    double,
    instant,
    iri,
    prefixes,
    statements,
    string,
    value,
)

MODEL = "urn:spl:model:Shop:"
XSD = "http://www.w3.org/2001/XMLSchema#"


@pytest.mark.parametrize(
    ("accept", "chosen"),
    [
        ("application/json", "json"),
        ("text/turtle", "turtle"),
        ("*/*", "turtle"),
        ("application/*", "json"),
        ("text/turtle;q=0.5, application/json", "json"),
        ("application/json;q=0.5, text/*", "turtle"),
        ("*/*;q=0.9, application/json;q=0.9", "json"),  # equal: the one named explicitly
        ("application/json;q=0, */*", "turtle"),
        ("application/json;q=nonsense, text/turtle;q=0.1", "turtle"),
        ("text/html", None),
        ("application/json;q=0, text/turtle;q=0", None),
    ],
)
def test_turtle_unless_json_is_preferred(accept: str, chosen: str | None) -> None:
    assert choose(accept) == chosen


def test_a_service_answers_406_when_nothing_is_acceptable_and_keeps_few_choices() -> None:
    negotiation = Negotiation()
    assert negotiation.negotiate(None) == "turtle"
    with pytest.raises(NotAcceptable):
        negotiation.negotiate("image/png")
    for n in range(Negotiation.LIMIT + 10):
        assert negotiation.negotiate(f"application/json, x/{n}") == "json"
    assert len(negotiation.chosen) == Negotiation.LIMIT


def _graph(*blocks: str) -> rdflib.Graph:
    return rdflib.Graph().parse(data=prefixes(MODEL) + "\n".join(blocks), format="turtle")


def test_hostile_texts_and_iris_stay_inside_their_terms() -> None:
    links = Links("http://store.example/")
    text = 'a "quote" \\ and\nnewline > . <urn:x> ;'
    subject = links('/Shop/records/1> <urn:evil> "x" .')
    graph = _graph(statements(subject, [("dcterms:title", string(text)), ("rdfs:comment", None)]))
    [(s, p, o)] = list(graph)
    assert str(s) == "http://store.example/Shop/records/1%3E%20%3Curn:evil%3E%20%22x%22%20."
    assert str(p) == "http://purl.org/dc/terms/title"
    assert str(o) == text
    assert links.url("/Shop") == "http://store.example/Shop"


def test_values_are_typed_as_the_model_says() -> None:
    subject = iri("urn:s")
    graph = _graph(
        statements(
            subject,
            [
                ("dt:Sale:price", value("double", 2.5)),
                ("dt:Sale:count", value("int", 7)),
                ("dt:Sale:paid", value("bool", True)),
                ("dt:Sale:note", value("string", "ok")),
                ("dt:Sale:big", double(math.inf)),
                ("dt:Sale:when", instant(0.25)),
            ],
        )
    )
    found = {str(p).removeprefix(MODEL): o for _, p, o in graph}
    assert (
        found["Sale:price"].datatype == rdflib.URIRef(XSD + "double")
        and found["Sale:price"].toPython() == 2.5
    )
    assert (
        found["Sale:count"].datatype == rdflib.URIRef(XSD + "long")
        and found["Sale:count"].toPython() == 7
    )
    assert found["Sale:paid"].toPython() is True
    assert str(found["Sale:note"]) == "ok"
    assert found["Sale:big"].toPython() == math.inf
    when = found["Sale:when"].toPython()
    assert (when.timestamp(), when.utcoffset()) == (0.25, datetime.timedelta(0))
    assert found["Sale:when"].datatype == rdflib.URIRef(XSD + "dateTime")


def test_instants_outside_years_1_to_9999_are_left_out() -> None:
    assert instant(-62135596800.0) == '"0001-01-01T00:00:00.000000Z"^^xsd:dateTime'
    assert instant(253402300800.0) is None
    assert double(math.nan) == '"NaN"^^xsd:double'
