"""resolved.xmi (written directly as text, or with the remembered look-ups) is byte for
byte what pyecore's own XMI writer writes, for every product of every shipped line, for
values that need escaping or that lxml itself must write, and for a model holding what
no shipped product does (empty and many-valued attributes, references out of the file);
the remembered roles are per feature."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st
from pyecore.ecore import EAttribute, EClass, EPackage, EReference, EString
from pyecore.resources import URI
from pyecore.resources.xmi import XMIResource

from spl.generators.bundle import resolved_xmi
from spl.resolver.analysis.formula import enumerate_products
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import ProductSelection

ROOT = Path(__file__).resolve().parents[2]
LINES = sorted(p for p in (ROOT / "product_lines").iterdir() if p.is_dir())


def pyecore_own(root) -> bytes:
    """What plain XMIResource (the same in-memory output) writes for ``root``."""
    resource = XMIResource(URI("resolved.xmi"))
    resource.append(root)
    output = resolved_xmi._InMemoryURI()
    try:
        resource.save(output=output)
    finally:
        resource.remove(root)
    return output.buffer.getvalue()


@pytest.mark.parametrize("directory", LINES, ids=lambda p: p.name)
def test_every_product_model_is_written_as_pyecore_writes_it(directory):
    line = load_product_line(directory)
    products = 0
    for features in enumerate_products(line.fm):
        system = resolve(line, ProductSelection("p", sorted(features))).product.system
        written = resolved_xmi.resolved_xmi(system)
        assert written == pyecore_own(system)
        # spl's own models take the direct text, not the fallback through pyecore
        assert resolved_xmi._XMIText(system).document(system) == written
        products += 1
    assert products >= 8


def test_a_model_beyond_the_shipped_ones_is_written_as_pyecore_writes_it():
    package = EPackage("demo", nsURI="http://example.org/demo", nsPrefix="demo")
    part = EClass("Part")
    special = EClass("Special", superclass=(part,))
    whole = EClass("Whole")
    part.eStructuralFeatures.append(EAttribute("name", EString))
    part.eStructuralFeatures.append(EAttribute("tags", EString, upper=-1))
    part.eStructuralFeatures.append(EAttribute("note", EString, default_value="n/a"))
    part.eStructuralFeatures.append(EReference("peer", part))
    part.eStructuralFeatures.append(EReference("peers", part, upper=-1))
    whole.eStructuralFeatures.append(EReference("parts", part, upper=-1, containment=True))
    whole.eStructuralFeatures.append(EReference("main", part, containment=True))
    package.eClassifiers.extend([part, special, whole])
    outside = part(name="outside")
    outside_resource = XMIResource(URI("outside.xmi"))
    outside_resource.append(outside)
    root = whole()
    a, b, c = part(name="a"), special(name="b"), part(name="c")
    root.parts.extend([a, b])
    root.main = c
    a.tags.extend(["x", "y"])
    b.tags.extend(["has space", "z"])
    c.tags.append("gone")
    c.tags.clear()  # set, then empty
    a.note = "n/a"  # set to the default
    b.note = "other"
    a.peer, b.peer = b, outside
    a.peers.extend([b, c, outside])
    assert resolved_xmi.resolved_xmi(root) == pyecore_own(root)


@pytest.mark.parametrize(
    "value",
    [
        "a&b<c>d\"e'f",
        "tab\there\r\n",
        "caf\u00e9 \u6771\u4eac \U0001f916",
        "del\x7f next\x85 sep\u2028",
        "",
        " ",
        "x" * 300,
        "bell\x07",  # no XML file can hold it: lxml's refusal, as pyecore's
        "lone \ud800",
    ],
)
def test_a_parameter_value_is_escaped_as_lxml_escapes_it(value):
    line = load_product_line(ROOT / "product_lines" / "mapping3d")
    features = sorted(next(iter(enumerate_products(line.fm))))
    system = resolve(line, ProductSelection("p", features)).product.system
    parameter = next(p for c in system.containers for n in c.nodes for p in n.parameters)
    parameter.value = value
    try:
        expected: bytes | str = pyecore_own(system)
    except ValueError as refused:
        expected = str(refused)
    try:
        written: bytes | str = resolved_xmi.resolved_xmi(system)
    except ValueError as refused:
        written = str(refused)
    assert written == expected


_MAPPING_SYSTEM: list = []


def _mapping_system():
    """One resolved mapping3d model, built once for the generated values below."""
    if not _MAPPING_SYSTEM:
        line = load_product_line(ROOT / "product_lines" / "mapping3d")
        features = sorted(next(iter(enumerate_products(line.fm))))
        _MAPPING_SYSTEM.append(resolve(line, ProductSelection("p", features)).product.system)
    return _MAPPING_SYSTEM[0]


@settings(max_examples=300, deadline=None)
@given(st.text(), st.text(alphabet=st.characters(max_codepoint=0x7F)))
def test_any_text_values_are_written_as_pyecore_writes_them(anything, ascii_text):
    system = _mapping_system()
    parameters = [p for c in system.containers for n in c.nodes for p in n.parameters]
    parameters[0].value = anything
    parameters[-1].value = ascii_text
    outcomes = []
    for write in (resolved_xmi.resolved_xmi, pyecore_own):
        try:
            outcomes.append(write(system))
        except ValueError as refused:  # a character no XML file can hold: lxml's refusal
            outcomes.append(str(refused))
    assert outcomes[0] == outcomes[1]


def test_a_reference_out_of_the_file_is_written_as_pyecore_writes_it():
    package = EPackage("refs", nsURI="http://example.org/refs", nsPrefix="refs")
    item = EClass("Item")
    item.eStructuralFeatures.append(EAttribute("name", EString))
    item.eStructuralFeatures.append(EReference("peer", item))
    item.eStructuralFeatures.append(EReference("items", item, upper=-1, containment=True))
    package.eClassifiers.append(item)
    outside = item(name="outside")
    XMIResource(URI("outside.xmi")).append(outside)
    root, inner = item(name="root"), item(name="inner")
    root.items.append(inner)
    inner.peer = root  # inside the file: the direct text
    assert resolved_xmi.resolved_xmi(root) == pyecore_own(root)
    inner.peer = outside  # another file's: pyecore's writer
    assert resolved_xmi.resolved_xmi(root) == pyecore_own(root)
