"""Linked Data of every store (docs/services.md, "Linked Data"): content negotiation
between Turtle (the default) and JSON, the Turtle terms (IRIs, literals, typed values,
statements) and the prefixes every document starts with. Every text goes through
``string()`` and every IRI through ``iri()``; the product's own names (its model's
vocabulary ``dt:``) reach a document only through ``prefixes()``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from datetime import UTC, datetime, timedelta
from typing import Any

TURTLE = "text/turtle"
JSON = "application/json"
MEDIA_TYPES = {TURTLE: "turtle", JSON: "json"}

HYBRIT = "https://hybr-it-projekt.de/ns/hybr-it#"
SPL = "urn:spl:vocab:"


def prefixes(model: str) -> str:
    """The prefixes of every document, ``dt:`` being the model's vocabulary ``model``."""
    return f"""@prefix rdf: <http://www.w3.org/1999/02/22-rdf-syntax-ns#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
@prefix sosa: <http://www.w3.org/ns/sosa/> .
@prefix dcterms: <http://purl.org/dc/terms/> .
@prefix prov: <http://www.w3.org/ns/prov#> .
@prefix ldp: <http://www.w3.org/ns/ldp#> .
@prefix sh: <http://www.w3.org/ns/shacl#> .
@prefix http: <http://www.w3.org/2011/http#> .
@prefix htm: <http://www.w3.org/2011/http-methods#> .
@prefix xhv: <http://www.w3.org/1999/xhtml/vocab#> .
@prefix hybrit: <{HYBRIT}> .
@prefix spl: <{SPL}> .
@prefix dt: <{model}> .

"""


# --- content negotiation ----------------------------------------------------------


class NotAcceptable(Exception):
    """No representation of the resource is acceptable to the client (406)."""


class Negotiation:
    """Content negotiation of one service, remembering the choice for the few Accept
    headers its clients send (not every one it sees: at most ``LIMIT``)."""

    LIMIT = 1024

    def __init__(self) -> None:
        self.chosen: dict[str, str | None] = {}

    def negotiate(self, accept: str | None) -> str:
        """``"turtle"`` or ``"json"`` for an Accept header: Turtle unless the header
        prefers JSON (R1.2); ``NotAcceptable`` when neither is acceptable."""
        if not accept:
            return "turtle"
        try:
            chosen = self.chosen[accept]
        except KeyError:
            chosen = choose(accept)
            if len(self.chosen) < self.LIMIT:
                self.chosen[accept] = chosen
        if chosen is None:
            raise NotAcceptable(accept)
        return chosen


def choose(accept: str) -> str | None:
    """``"turtle"``, ``"json"`` or None (neither acceptable) for an Accept header. Each
    media type takes the quality of the most specific range that matches it; equal
    qualities go to the type named explicitly, then to Turtle."""
    ranges = []
    for part in accept.split(","):
        media, _, parameters = part.partition(";")
        media = media.strip().lower()
        if not media:
            continue
        quality = 1.0
        for parameter in parameters.split(";"):
            name, _, value = parameter.partition("=")
            if name.strip().lower() == "q":
                try:
                    quality = float(value.strip())
                except ValueError:
                    quality = -1.0  # a malformed range is ignored
                if not 0.0 <= quality <= 1.0:
                    quality = -1.0
        if quality >= 0.0:
            ranges.append((media, quality))
    best: tuple[float, int, int] | None = None
    chosen = None
    for preference, (media_type, name) in enumerate(reversed(list(MEDIA_TYPES.items()))):
        kind = media_type.split("/")[0]
        match = None  # (specificity, quality) of the most specific range matching
        for media, quality in ranges:
            specificity = (
                2
                if media == media_type
                else 1
                if media == f"{kind}/*"
                else 0
                if media == "*/*"
                else -1
            )
            if specificity >= 0 and (match is None or specificity > match[0]):
                match = (specificity, quality)
        if match is None or match[1] <= 0.0:
            continue
        key = (match[1], match[0], preference)
        if best is None or key > best:
            best, chosen = key, name
    return chosen


# --- Turtle terms -----------------------------------------------------------------

_IRI_ESCAPES = {c: f"%{c:02X}" for c in [*range(0x21), *b'<>"{}|^`\\']}
_STRING_ESCAPES = {ord("\\"): "\\\\", ord('"'): '\\"', ord("\n"): "\\n", ord("\r"): "\\r"}
EPOCH = datetime(1970, 1, 1, tzinfo=UTC)


def iri(value: str) -> str:
    """An IRIREF: characters Turtle does not allow in one are percent-encoded (a Host
    header or a query reaches IRIs; model names are identifiers anyway)."""
    return "<" + value.translate(_IRI_ESCAPES) + ">"


def string(value: str) -> str:
    return '"' + value.translate(_STRING_ESCAPES) + '"'


def typed(lexical: str, datatype: str) -> str:
    return f'"{lexical}"^^{datatype}'


def double(value: float) -> str:
    if math.isnan(value):
        lexical = "NaN"
    elif math.isinf(value):
        lexical = "INF" if value > 0 else "-INF"
    else:
        lexical = repr(float(value))
    return typed(lexical, "xsd:double")


def instant(seconds: float) -> str | None:
    """A timestamp (seconds since the epoch) as an xsd:dateTime in UTC; None outside
    years 1 to 9999 (posts refuse such timestamps)."""
    try:
        moment = EPOCH + timedelta(seconds=seconds)
    except (OverflowError, ValueError):
        return None
    return typed(moment.isoformat(timespec="microseconds").replace("+00:00", "Z"), "xsd:dateTime")


def value(kind: str, item: Any) -> str:
    if kind == "double":
        return double(item)
    if kind == "int":
        return typed(str(int(item)), "xsd:long")
    if kind == "bool":
        return "true" if item else "false"
    return string(str(item))


DATATYPES = {
    "double": "xsd:double",
    "int": "xsd:long",
    "string": "xsd:string",
    "bool": "xsd:boolean",
}


def data_class(type_name: str) -> str:
    return f"dt:{type_name}"


def predicate(type_name: str, field: str) -> str:
    return f"dt:{type_name}:{field}"


def statements(subject: str, pairs: Iterable[tuple[str, str | None]]) -> str:
    """``subject p1 o1 ; p2 o2 .`` (objects None are left out)."""
    body = " ;\n    ".join(f"{p} {o}" for p, o in pairs if o is not None)
    return f"{subject} {body} .\n"


# --- the IRIs of a request's resources ---------------------------------------------


class Links:
    """The IRIs of the store's resources under the base URL a request came to."""

    def __init__(self, base: str) -> None:
        self.base = base.rstrip("/")

    def url(self, path: str) -> str:
        return self.base + path

    def __call__(self, path: str) -> str:
        return iri(self.base + path)
