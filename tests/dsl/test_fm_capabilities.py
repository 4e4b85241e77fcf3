"""Capability conditions in the .fm language: syntax, errors, printer and interchange."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.core.emf_compare import differences
from spl.dsl.fm import language as fm
from spl.dsl.fm.printer import format_capabilities, print_model
from spl.dsl.interop.featureide import parse_featureide
from spl.dsl.interop.featureide_writer import write_featureide
from spl.dsl.interop.uvl import parse_uvl, write_uvl

ROOT = Path(__file__).resolve().parents[2]
MODEL = (
    "feature model M\n"
    "root R {\n"
    "    mandatory Base xor {\n"
    '        YouBot { capability base = "youbot" }\n'
    '        Roomba { capability base = "roomba" and wheels >= 2 }\n'
    "    }\n"
    "    optional PC {\n"
    "        capability onboard_pc\n"
    '        capability cpu.cores >= 4 and sensors has "x and y" and gpu != false\n'
    "    }\n"
    "}\n"
)


def conditions(model, name: str) -> list[tuple]:
    feature = next(f for f in fm.all_features(model) if f.name == name)
    return [
        (c.key, c.operator, c.value, c.valueType.name if c.operator else None)
        for c in feature.capabilities
    ]


def test_conditions_are_parsed_typed_and_located() -> None:
    model = fm.parse_text(MODEL, "m.fm")
    assert conditions(model, "YouBot") == [("base", "=", "youbot", "string")]
    assert conditions(model, "Roomba") == [
        ("base", "=", "roomba", "string"),
        ("wheels", ">=", "2", "int"),
    ]
    assert conditions(model, "PC") == [
        ("onboard_pc", "", None, None),
        ("cpu.cores", ">=", "4", "int"),
        ("sensors", "has", "x and y", "string"),
        ("gpu", "!=", "false", "bool"),
    ]
    roomba = next(f for f in fm.all_features(model) if f.name == "Roomba")
    second = roomba.capabilities[1]
    assert (second.srcFile, second.srcLine, second.srcCol) == ("m.fm", 5, 49)


def test_printer_writes_one_line_per_condition_and_round_trips() -> None:
    model = fm.parse_text(MODEL)
    text = print_model(model)
    assert '        capability cpu.cores >= 4\n        capability sensors has "x and y"\n' in text
    again = fm.parse_text(text)
    assert list(differences(model, again)) == []
    assert print_model(again) == text


def test_uvl_and_featureide_carry_the_conditions_in_a_capability_attribute() -> None:
    model = fm.parse_text(MODEL)
    uvl = write_uvl(model)
    assert (
        'PC {capability \'onboard_pc and cpu.cores >= 4 and sensors has "x and y" and '
        "gpu != false'}" in uvl
    )
    assert list(differences(model, parse_uvl(uvl, "m.uvl", "M"))) == []
    xml = write_featureide(model)
    assert b'name="capability" type="string" value="base = &quot;youbot&quot;"' in xml
    back = parse_featureide(xml, "M.xml")
    assert list(differences(model.root, back.root)) == []
    pc = next(f for f in fm.all_features(back) if f.name == "PC")
    assert format_capabilities(pc) == (
        'onboard_pc and cpu.cores >= 4 and sensors has "x and y" and gpu != false'
    )


def test_the_shipped_mapping_line_maps_hardware_to_capabilities() -> None:
    model = fm.parse_file(ROOT / "product_lines" / "mapping3d" / "mapping.fm")
    mapped = {f.name: format_capabilities(f) for f in fm.all_features(model) if f.capabilities}
    assert mapped == {
        "YouBot": 'base = "youbot"',
        "Roomba": 'base = "roomba"',
        "Stereo": 'sensors has "stereo_camera"',
        "Depth": 'sensors has "depth_camera"',
        "AdditionalPC": "onboard_pc",
    }


@pytest.mark.parametrize(
    ("body", "col", "expected"),
    [
        ('capability base >= "big"', 34, "capability base >= needs a number"),
        ("capability = 3", 34, "capability name"),
        ("capability a == 3", 37, "syntax error"),
        ("capability a = 'x'", 38, "syntax error"),
        ('capability and = "x"', 34, "capability name"),
        ('attribute capability : string = "x"', 23, "reserved"),
    ],
)
def test_bad_conditions_are_located_errors(body: str, col: int, expected: str) -> None:
    with pytest.raises(ModelError) as info:
        fm.parse_text(f"feature model M\nroot R {{ optional A {{ {body} }} }}\n", "bad.fm")
    (diagnostic,) = info.value.diagnostics
    assert (diagnostic.location.line, diagnostic.location.col) == (2, col)
    assert expected in diagnostic.message


@pytest.mark.parametrize(
    ("attribute", "expected"),
    [
        ("capability 'base = = 1'", "syntax error: expected number, string or true or false"),
        ("capability 3", "capability takes a condition string"),
        ("capability 'a >= \"x\"'", "needs a number"),
    ],
)
def test_a_bad_capability_attribute_in_uvl_is_located_at_the_attribute(
    attribute: str, expected: str
) -> None:
    text = f"features\n\tR\n\t\toptional\n\t\t\tA {{{attribute}}}\n"
    with pytest.raises(ModelError) as info:
        parse_uvl(text, "bad.uvl")
    (diagnostic,) = info.value.diagnostics
    assert (diagnostic.location.line, diagnostic.location.col) == (4, 7)
    assert expected in diagnostic.message


def test_a_bad_capability_attribute_in_featureide_is_located() -> None:
    xml = (
        b'<featureModel><struct><and name="R"><feature name="A">'
        b'<attribute name="capability" type="string" value="x &gt;="/>'
        b"</feature></and></struct></featureModel>"
    )
    with pytest.raises(ModelError) as info:
        parse_featureide(xml, "bad.xml")
    (diagnostic,) = info.value.diagnostics
    assert diagnostic.location.file == "bad.xml" and "capability 'x >='" in diagnostic.message
