"""The architecture diagram's Digraph, quoting without graphviz's argument checks, writes
exactly the source graphviz's own Digraph writes, for every product of every shipped
line, and its quoting tells a plain text from the same text escaped."""

from __future__ import annotations

from pathlib import Path

import graphviz
import pytest
from graphviz import quoting

from spl.generators.diagrams import architecture as diagrams, graphviz_output
from spl.resolver.analysis.formula import enumerate_products
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import ProductSelection

ROOT = Path(__file__).resolve().parents[2]
LINES = sorted(p for p in (ROOT / "product_lines").iterdir() if p.is_dir())


class _GraphvizOwn(graphviz.Digraph):
    """graphviz's own Digraph, taking (and ignoring) the memo spl's takes."""

    def __init__(self, *args, quoted=None, **kwargs):
        super().__init__(*args, **kwargs)


@pytest.mark.parametrize("directory", LINES, ids=lambda p: p.name)
def test_every_product_diagram_source_is_graphviz_own(directory, monkeypatch):
    line = load_product_line(directory)
    products = 0
    for features in enumerate_products(line.fm):
        product = resolve(line, ProductSelection("p", sorted(features))).product
        fast = diagrams.generate(product, render=False)
        with monkeypatch.context() as patch:
            patch.setattr(diagrams, "Digraph", _GraphvizOwn)
            own = diagrams.generate(product, render=False)
        assert fast == own
        products += 1
    assert products >= 8


@pytest.mark.parametrize("first_plain", [True, False])
def test_an_escaped_text_quotes_apart_from_the_same_plain_text(first_plain):
    # '<b>x</b>' plain is an HTML-like label (unquoted); escaped, it is a literal text
    texts = ["<<b>x</b>>", graphviz.escape("<<b>x</b>>")]
    if not first_plain:
        texts.reverse()
    for text in texts:
        assert graphviz_output._quote(text) == quoting.quote(text)
    assert graphviz_output._quote(texts[0]) != graphviz_output._quote(texts[1])


@pytest.mark.parametrize(
    "identifier", ["a", "a b", "a.b:i_x", "a b:p q:sw", "node", "-4.2", 'say "hi"', ""]
)
def test_ids_attributes_and_edges_quote_as_graphviz_does(identifier):
    assert graphviz_output._quote(identifier) == quoting.quote(identifier)
    assert graphviz_output._quote_edge(identifier) == quoting.quote_edge(identifier)
    attributes = {"z": identifier, "a": "1", "skip": None}
    assert graphviz_output._attr_list(identifier, kwargs=attributes) == quoting.attr_list(
        identifier, kwargs=attributes
    )
    assert graphviz_output._a_list(None, attributes=[("k", identifier)]) == quoting.a_list(
        None, attributes=[("k", identifier)]
    )


def test_a_diagram_and_its_subgraphs_share_the_memo_they_are_given(monkeypatch):
    line = load_product_line(ROOT / "product_lines" / "mapping3d")
    product = resolve(
        line, ProductSelection("p", sorted(next(enumerate_products(line.fm))))
    ).product
    memo: dict = {}
    first = diagrams.architecture_graph(product.system, product, memo).source
    quoted = []
    monkeypatch.setattr(graphviz_output, "_quote", lambda text: quoted.append(text) or text)
    again = diagrams.architecture_graph(product.system, product, memo).source
    assert again == first and quoted == []  # every text, subgraphs' included, remembered
    alone = diagrams.architecture_graph(product.system, product).source
    assert quoted and alone != first  # without one, it quotes on its own (here: wrongly)
