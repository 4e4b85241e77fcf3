"""The YAML check of a bundle file gives PyYAML's safe loader's verdict and message,
whether the stream was decided from libyaml's events or loaded; every YAML file of the
shipped products is decided from the events (the check's fast path is the one taken)."""

from __future__ import annotations

import pytest
import yaml
from hypothesis import given, settings, strategies as st

from spl.generators.bundle import validation as bundle_validation
from spl.generators.bundle.validation import YAML_LOADER, _loads_plainly, _yaml
from spl.generators.bundle.writer import bundle_files

from support.hypothesis_budget import examples
from support.shipped_products import shipped_products

pytestmark = pytest.mark.skipif(
    bundle_validation._YAML_PARSER is None, reason="PyYAML without libyaml"
)


def loader_verdict(data: bytes) -> list[str]:
    """What the check said before it read events: the loader's own verdict."""
    try:
        list(yaml.load_all(data, Loader=YAML_LOADER))
    except (yaml.YAMLError, ValueError) as exc:
        return [f"f.yaml: not YAML: {exc}"]
    return []


STREAMS = [
    b"",
    b"a: 1\nb: [x, 'y', \"z\"]\nc: {d: null, e: true}\n",
    b"- a\n- b: c\n  d: |\n    text\n    more\n",
    b"---\n...\n---\nkind: Service\n",
    b"a: 0b_\n",  # resolved as an int, which int() refuses
    b"a: 2024-13-45\n",  # a timestamp with no such month
    b"a: 2001-12-14t21:59:43.10-05:00\nb: 1.5e+3\nc: .inf\n",
    b"? [a]\n: b\n",  # a sequence as a key: unhashable
    b"? {a: 1}\n: b\n",
    b"a: *x\n",  # undefined alias
    b"a: &x 1\nb: *x\n",
    b"a: !!str 1\nb: !!int x\n",
    b"a: !custom 1\n",
    b"<<: {a: 1}\nb: 2\n",
    b"a: =\n",
    b"= : 1\n",
    b"a: [\n",
    b"a: b: c\n",
    b"\t- a\n",
    b"%YAML 1.1\n--- a\n",
    b"\xff\xfe",
    b"a: \x00\n",
    b"a: 1\na: 2\n",
]


@pytest.mark.parametrize("data", STREAMS)
def test_verdict_is_the_loaders(data):
    assert _yaml("f.yaml", data) == loader_verdict(data)


scalars = st.one_of(
    st.text(max_size=8),
    st.integers(),
    st.booleans(),
    st.none(),
    st.floats(allow_nan=False),
    st.sampled_from(["0b_", "0x_", "1_0", "2024-13-45", "yes", "~", "=", "<<", "._", "0o9"]),
)
documents = st.recursive(
    scalars,
    lambda inner: (
        st.lists(inner, max_size=4)
        | st.dictionaries(st.text(max_size=5) | st.integers(), inner, max_size=4)
    ),
    max_leaves=12,
)


@settings(max_examples=examples(200), deadline=None)
@given(documents, st.data())
def test_verdict_on_written_and_damaged_streams(document, data):
    text = yaml.safe_dump(document, allow_unicode=True).encode()
    for stream in (text, text.replace(b"'", b"")):  # unquoted: other tags, other errors
        assert _yaml("f.yaml", stream) == loader_verdict(stream)
    cut = data.draw(st.integers(0, len(text)))
    noise = data.draw(st.binary(max_size=4))
    damaged = text[:cut] + noise + text[cut:]
    assert _yaml("f.yaml", damaged) == loader_verdict(damaged)


def test_shipped_products_yaml_is_decided_from_events():
    checked = 0
    for _, product in shipped_products():
        for path, data in bundle_files(product).items():
            if path.endswith((".yaml", ".yml")):
                assert _loads_plainly(data), path
                checked += 1
    assert checked > 40  # Kubernetes manifests, kustomizations, deploy files
