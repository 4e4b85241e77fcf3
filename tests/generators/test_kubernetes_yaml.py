"""kubernetes_yaml writes the bytes PyYAML's emitters write (libyaml's and the pure-Python
one) for every document it takes, declines the rest, and takes every document of the
shipped products (so what the bundles hold is what it writes)."""

from __future__ import annotations

import pytest
import yaml
from hypothesis import example, given, settings, strategies as st

from spl.generators.bundle.writer import build_bundle
from spl.generators.kubernetes import objects as kubernetes_objects
from spl.generators.kubernetes.objects import _Literal
from spl.generators.kubernetes.yaml_text import block_yaml

from support.hypothesis_budget import examples
from support.shipped_products import shipped_products


def by_pyyaml(documents, dumper) -> str:
    return yaml.dump_all(
        documents, Dumper=dumper, sort_keys=False, default_flow_style=False, width=2**16
    )


def assert_as_pyyaml(documents) -> str | None:
    written = block_yaml(documents, _Literal)
    if written is not None:
        for dumper in (kubernetes_objects.DUMPER, kubernetes_objects.PYTHON_DUMPER):
            assert written == by_pyyaml(documents, dumper)
    return written


# strings near the edges of what is written plain, quoted or declined
words = st.sampled_from(
    [
        "app",
        "a.b/c",
        "x=1",
        "1",
        "0x1F",
        "1_0",
        "1:20",
        "yes",
        "No",
        "null",
        "~",
        "true",
        "2024-01-01",
        "1.5",
        ".inf",
        "-",
        "-a",
        "a-",
        "a:",
        ":a",
        "a:b",
        "@a",
        "a@b",
        "=",
        "<<",
        "#a",
        "a#b",
        "---",
        "...",
        "a b",
        "a  b",
        " a",
        "a ",
        "é",
        "a\tb",
        "'",
        '"',
        "",
        "x" * 130,
        "eclipse/zenoh:1.10.0",
        "+1",
        "0o7",
        "09",
        "1e3",
        "a,b",
        "[a]",
        "%a",
    ]
)
strings = st.one_of(
    words,
    st.text(max_size=6),
    st.from_regex(r"[-a-z0-9_./:=@+ ,#'\"!?{}%&*|>$]{1,12}", fullmatch=True),
)
literals = st.one_of(
    st.sampled_from(
        [
            "a\n",
            "a\nb\n",
            "a\n\nb\n",
            "<a>\n  <b/>\n</a>\n",
            " a\n",
            "a \nb\n",
            "a",
            "a\n\n",
            "\na\n",
            "a\tb\n",
            "é\n",
        ]
    ),
    st.text(alphabet="ab <>/\n", max_size=12),
).map(_Literal)
scalars = st.one_of(strings, st.integers(), st.booleans(), st.none())
values = st.recursive(
    st.one_of(scalars, literals, st.just({}), st.just([])),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(strings, inner, max_size=3),
    max_leaves=10,
)
documents = st.lists(
    st.dictionaries(strings, values, min_size=1, max_size=4), min_size=1, max_size=3
)


# the same, from values mostly of the shapes it takes: most streams are written directly
taken_strings = st.one_of(
    st.sampled_from(["1", "0x1F", "1:20", "yes", "null", "true", "2024-01-01", "1.5", "-c"]),
    st.from_regex(
        r"-?[a-z0-9_/][-a-z0-9_./=@+,'\"!?{}%&*|>$#]{0,8}( [a-z0-9_./-]{1,4})?(:[a-z]{1,3})?",
        fullmatch=True,
    ),
)
taken_literals = st.from_regex(r"[a-z<][a-z <>/=\n]{0,12}[a-z>]\n", fullmatch=True).map(_Literal)
taken_values = st.recursive(
    st.one_of(taken_strings, st.integers(), st.booleans(), st.none(), st.just({}), st.just([])),
    lambda inner: (
        st.lists(inner, max_size=3)
        | st.dictionaries(taken_strings, inner | taken_literals, max_size=3)
    ),
    max_leaves=10,
)
taken_documents = st.lists(
    st.dictionaries(taken_strings, taken_values | taken_literals, min_size=1, max_size=4),
    min_size=1,
    max_size=3,
)


@settings(max_examples=examples(300), deadline=None)
@given(taken_documents | documents)
@example([{"a": {"b": [{"c": 1, "d": [1, [2, 3]]}, []], "e": {}}, "f": _Literal("x\n y\n")}])
def test_writes_what_pyyaml_writes_or_declines(docs):
    assert_as_pyyaml(docs)


@pytest.mark.parametrize(
    "docs",
    [
        [{"a": "x"}, {"b": ["1", 2, True, None]}],
        [{"k": {"l": [{"m": "n", "o": ["p", {"q": "r"}]}]}}],
        [{"data": {"launch.xml": _Literal("<launch>\n\n  <node/>\n</launch>\n")}}],
        [{"port": 7447, "name": "1.10", "on": "off", "image": "eclipse/zenoh:1.10.0"}],
    ],
)
def test_takes_the_shapes_of_manifests(docs):
    assert assert_as_pyyaml(docs) is not None


@pytest.mark.parametrize(
    "docs",
    [
        [{"a": "two words: here"}],
        [{"a": "x" * 1001}],
        [{"k" * 128: 1}],
        [{"a": _Literal("trailing \nspace\n")}],
        [{"a": [_Literal("in a sequence\n")]}],
        [{"a": 1.5}],
        [{}],
        [{1: "a"}],
    ],
)
def test_declines_what_it_does_not_write(docs):
    assert block_yaml(docs, _Literal) is None
    by_pyyaml(docs, kubernetes_objects.DUMPER)  # PyYAML writes them, through render


def test_every_shipped_manifest_is_written_directly(monkeypatch):
    declined = []

    def writer(documents, literal, plain):
        written = block_yaml(documents, literal, plain)
        if written is None:
            declined.append(documents)
        return written

    monkeypatch.setattr(kubernetes_objects, "WRITER", writer)
    count = 0
    for _, product in shipped_products():
        files = build_bundle(product).files
        count += sum(path.startswith("kubernetes/") for path in files)
    assert count > 40
    assert declined == []
