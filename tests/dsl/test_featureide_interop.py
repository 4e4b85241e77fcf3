"""FeatureIDE XML: the real twins agree with their UVL, round trips, hostile input."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.core.emf_compare import differences
from spl.dsl.fm import language as fm
from spl.dsl.interop.featureide import parse_featureide, read_featureide
from spl.dsl.interop.featureide_writer import write_featureide
from spl.dsl.interop.interchange import original_name
from spl.dsl.interop.uvl import read_uvl, write_uvl

from support.fm_semantics import equivalent, products, relations
from support.real_models import REAL_MODELS

ROOT = Path(__file__).resolve().parents[2]
DATA = REAL_MODELS
TWINS = ["axTLS", "berkeleydb"]


def test_twins_exist() -> None:
    for name in TWINS:
        assert (DATA / f"{name}.xml").is_file() and (DATA / f"{name}.uvl").is_file()


@pytest.mark.parametrize("name", TWINS)
def test_xml_twin_gives_the_same_model_as_uvl(name: str) -> None:
    from_xml = read_featureide(DATA / f"{name}.xml")
    from_uvl = read_uvl(DATA / f"{name}.uvl")
    assert relations(from_xml) == relations(from_uvl)
    assert len(from_xml.constraints) == len(from_uvl.constraints)
    for x, u in zip(from_xml.constraints, from_uvl.constraints, strict=True):
        assert equivalent(x.formula, u.formula), (x.srcLine, u.srcLine)


@pytest.mark.parametrize("name", TWINS)
def test_xml_round_trip_is_exact(name: str) -> None:
    model = read_featureide(DATA / f"{name}.xml")
    again = parse_featureide(write_featureide(model), "out.xml", default_name=name)
    assert list(differences(model, again)) == []


def test_berkeleydb_one_child_alt_is_read_as_featureide_reads_it() -> None:
    model = read_featureide(DATA / "berkeleydb.xml")
    root = model.root
    assert [(g.kind.name, [c.name for c in g.features]) for g in root.groups] == [
        ("optional", ["BerkeleyDB"])
    ]


def test_export_keeps_products_of_small_models() -> None:
    for path in (
        ROOT / "product_lines/mapping3d/mapping.fm",
        ROOT / "tests/models/fm/spec_example.fm",
    ):
        model = fm.parse_file(path)
        data = write_featureide(model)
        again = parse_featureide(data, "out.xml", default_name=model.name)
        assert relations(model) == relations(again)
        for mine, theirs in zip(again.constraints, model.constraints, strict=True):
            assert equivalent(mine.formula, theirs.formula)
        assert products(again) == products(model)
        by_name = {f.name: f for f in fm.all_features(again)}
        for feature in fm.all_features(model):
            mine = by_name[feature.name]
            assert (mine.sharing.mode.name if mine.sharing else None) == (
                feature.sharing.mode.name if feature.sharing else None
            )
            assert [(a.name, a.type.name, a.value) for a in mine.attributes] == [
                (a.name, a.type.name, a.value) for a in feature.attributes
            ]


def test_cardinality_groups_are_written_as_their_featureide_equivalent() -> None:
    model = fm.parse_text(
        "feature model M root R {\n"
        " mandatory A group [1..1] { A1 A2 }\n"
        " mandatory B group [1..*] { B1 B2 }\n"
        " mandatory C group [0..*] { C1 C2 }\n"
        " mandatory D xor { D1 }\n"
        "}\n"
        "constraints { A1 excludes B1  C1 requires D }"
    )
    again = parse_featureide(write_featureide(model), "out.xml", default_name="M")
    kinds = {f.name: [g.kind.name for g in f.groups] for f in fm.all_features(again)}
    assert kinds["A"] == ["alternative"] and kinds["B"] == ["or"]
    assert kinds["C"] == ["optional"] and kinds["D"] == ["mandatory"]
    assert products(again) == products(model)


def test_shapes_featureide_cannot_express_are_reported() -> None:
    model = fm.parse_text(
        "feature model M\nroot R {\n  mandatory A\n  xor { B C }\n  group [2..3] { D E F G }\n}\n",
        "m.fm",
    )
    with pytest.raises(ModelError) as info:
        write_featureide(model)
    (diagnostic,) = info.value.diagnostics
    assert (diagnostic.location.file, diagnostic.location.line) == ("m.fm", 2)
    assert "FeatureIDE XML cannot express its groups (mandatory, [2..3])" in diagnostic.message
    # moving the group under a feature of its own would not help: say what would
    assert "no group cardinality [2..3] of 4 features" in diagnostic.message
    assert "or group with a constraint" in diagnostic.message


def test_two_groups_of_one_feature_are_reported_with_the_move_that_helps() -> None:
    model = fm.parse_text("feature model M\nroot R {\n  xor { B C }\n  or { D E }\n}\n", "m.fm")
    with pytest.raises(ModelError) as info:
        write_featureide(model)
    (diagnostic,) = info.value.diagnostics
    assert diagnostic.message.endswith(
        "(xor, or); move each xor/or group under an abstract feature of its own"
    )


def test_odd_names_are_sanitised_and_written_back() -> None:
    data = (
        b'<featureModel><struct><and abstract="true" name="My Root">'
        b'<feature mandatory="true" name="a-b"/><feature name="a_b"/>'
        b'<alt name="x.y"><feature name="1"/><feature name="not"/></alt>'
        b"</and></struct><constraints><rule><imp><var>a-b</var><not><var>1</var></not>"
        b"</imp></rule><rule><conj><var>a_b</var><var>x.y</var><var>not</var></conj></rule>"
        b"</constraints></featureModel>"
    )
    model = parse_featureide(data, "odd.xml")
    names = [f.name for f in fm.all_features(model)]
    assert names == ["My_Root", "a_b_2", "a_b", "x_y", "_1", "not_"]
    assert [original_name(f) for f in fm.all_features(model)] == [
        "My Root",
        "a-b",
        "a_b",
        "x.y",
        "1",
        "not",
    ]
    conj = model.constraints[1].formula  # n-ary conj folds to the left
    assert conj.operator == "and" and conj.left.operator == "and"
    written = write_featureide(model)
    assert b'name="a-b"' in written and b"<var>x.y</var>" in written
    again = parse_featureide(written, "again.xml")
    assert list(differences(model, again)) == []
    # UVL cannot quote a name with a dot: exporting says so instead of renaming
    with pytest.raises(ModelError, match=r"'x\.y' cannot be written in UVL"):
        write_uvl(model)


@pytest.mark.parametrize(
    ("data", "line", "message"),
    [
        (b"<featureModel><struct><and name='R'>\n<feature name='A'>\n</struct>", 3, "XML syntax"),
        (b"<model/>", 1, "expected <featureModel>"),
        (
            b"<featureModel><struct><and name='R'><feature name='A'/></and></struct>\n"
            b"<constraints><rule><imp><var>A</var>\n<var>B</var></imp></rule></constraints>"
            b"</featureModel>",
            3,
            "unknown feature B",
        ),
        (
            b"<featureModel><struct><and name='R'>\n<feature name='A'/>\n<feature name='A'/>"
            b"</and></struct></featureModel>",
            3,
            "duplicate feature A",
        ),
        (
            b"<featureModel><struct><and name='R'><feature name='A'/></and></struct>\n"
            b"<constraints><rule><atmost1><var>A</var></atmost1></rule></constraints>"
            b"</featureModel>",
            2,
            "unsupported constraint element",
        ),
    ],
)
def test_located_errors(data: bytes, line: int, message: str) -> None:
    with pytest.raises(ModelError) as info:
        parse_featureide(data, "bad.xml")
    first = info.value.diagnostics[0]
    assert first.location.file == "bad.xml" and first.location.line == line
    assert message in first.message


def test_external_entities_are_never_loaded() -> None:
    data = (
        b'<?xml version="1.0"?>\n<!DOCTYPE featureModel [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
        b'<featureModel><struct><and name="R"><feature name="A&x;"/></and></struct></featureModel>'
    )
    with pytest.raises(ModelError) as info:
        parse_featureide(data, "xxe.xml")
    assert "root:" not in str(info.value)


def test_a_boolean_attribute_that_is_not_one_is_refused(tmp_path) -> None:
    # was read as false: mandatory="yes" made a feature optional (berkeleydb's product
    # count went from 4,080,389,785 to 10,134,159,385 without a word)
    path = tmp_path / "m.xml"
    path.write_text(
        '<?xml version="1.0"?>\n<featureModel><struct><and name="R" abstract="1">\n'
        '<feature mandatory="yes" name="A"/>\n<feature mandatory="0" abstract="perhaps" '
        'name="B"/>\n<feature mandatory="true" name="C"/></and></struct></featureModel>\n',
        encoding="utf-8",
    )
    with pytest.raises(ModelError) as caught:
        read_featureide(path)
    assert [str(d) for d in caught.value.diagnostics] == [
        f'{path}:3:1: error: mandatory="yes": expected true or false',
        f'{path}:4:1: error: abstract="perhaps": expected true or false',
    ]
    path.write_text(path.read_text().replace('"yes"', '"1"').replace('"perhaps"', '"false"'))
    model = read_featureide(path)
    assert model.root.abstract
    kinds = {f.name: g.kind.name for g in model.root.groups for f in g.features}
    assert kinds == {"A": "mandatory", "B": "optional", "C": "mandatory"}
