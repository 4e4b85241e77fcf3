"""Feature-model diagram (the mapping paper's Fig. 5) of the mapping line's feature model."""

from __future__ import annotations

from typing import Any

import pytest
from lxml import etree

from spl.dsl.fm.printer import format_formula
from spl.generators.diagrams.feature_model import SELECTED_GREEN, feature_model_graph
from spl.generators.diagrams.graphviz_output import render_bytes
from spl.metamodels import fm

SVG = {"s": "http://www.w3.org/2000/svg"}
FIG5_SELECTION = {"Mapping", "MobileBase", "YouBot", "PerceptionSensor", "Stereo"} | {
    "AdditionalPC",
    "Environment",
    "Room",
    "SharedMap",
}


def _group(parent: Any, kind: str, *children: Any, lower: int = 0, upper: int = 0) -> None:
    F = fm()
    group = F.Group(kind=F.GroupKind.getEEnumLiteral(kind), lower=lower, upper=upper)
    group.features.extend(children)
    parent.groups.append(group)


def _ref(name: str, features: dict[str, Any]) -> Any:
    return fm().FeatureRef(feature=features[name])


def mapping_feature_model() -> Any:
    """docs/product-lines.md, plus an or-group and a cardinality group."""
    F = fm()
    names = [
        "Mapping",
        "MobileBase",
        "YouBot",
        "Roomba",
        "PerceptionSensor",
        "Stereo",
        "Depth",
        "AdditionalPC",
        "Environment",
        "Room",
        "Corridor",
        "SharedMap",
        "Logging",
        "Console",
        "File",
        "Robots",
        "One",
        "Many",
    ]
    f = {n: F.Feature(name=n) for n in names}
    for abstract in ("MobileBase", "PerceptionSensor", "Environment"):
        f[abstract].abstract = True
    f["SharedMap"].sharing = F.SharingConfig(mode=F.SharingMode.protected)
    f["Logging"].attributes.append(
        F.Attribute(name="rate", type=F.AttributeType.double, value="1.0")
    )
    _group(f["Mapping"], "mandatory", f["MobileBase"], f["PerceptionSensor"], f["Environment"])
    _group(f["Mapping"], "mandatory", f["SharedMap"])
    _group(f["Mapping"], "optional", f["AdditionalPC"], f["Logging"], f["Robots"])
    _group(f["MobileBase"], "alternative", f["YouBot"], f["Roomba"])
    _group(f["PerceptionSensor"], "alternative", f["Stereo"], f["Depth"])
    _group(f["Environment"], "alternative", f["Room"], f["Corridor"])
    _group(f["Logging"], "or", f["Console"], f["File"])
    _group(f["Robots"], "cardinality", f["One"], f["Many"], lower=1, upper=-1)
    model = F.FeatureModel(name="Mapping3D", root=f["Mapping"])
    excludes = F.BinaryFormula(
        operator="excludes", left=_ref("Roomba", f), right=_ref("AdditionalPC", f)
    )
    implies = F.BinaryFormula(
        operator="implies",
        left=_ref("Stereo", f),
        right=F.BinaryFormula(
            operator="or", left=_ref("AdditionalPC", f), right=F.Not(operand=_ref("Depth", f))
        ),
    )
    model.constraints.extend([F.Constraint(formula=excludes), F.Constraint(formula=implies)])
    return model


@pytest.fixture(scope="module")
def svg_root():
    graph = feature_model_graph(
        mapping_feature_model(), FIG5_SELECTION, formula_text=format_formula
    )
    return etree.fromstring(render_bytes(graph, "svg"))


def nodes(root: etree._Element) -> dict[str, etree._Element]:
    return {
        g.findtext("s:title", namespaces=SVG): g
        for g in root.iterfind(".//s:g[@class='node']", SVG)
    }


def edges(root: etree._Element) -> dict[str, etree._Element]:
    return {
        g.findtext("s:title", namespaces=SVG): g
        for g in root.iterfind(".//s:g[@class='edge']", SVG)
    }


def test_names_every_feature_and_constraint(svg_root):
    shown = [t.text for t in svg_root.iterfind(".//s:text", SVG)]
    for feature in mapping_feature_model().eAllContents():
        if feature.eClass.name == "Feature":
            assert feature.name in shown
    assert "Roomba excludes AdditionalPC" in shown
    # written as the .fm language writes it: "or" binds tighter than "=>"
    assert "Stereo => AdditionalPC or not Depth" in shown
    assert "rate : double = 1.0" in shown and "sharing protected" in shown


def test_selection_in_green_and_the_rest_white(svg_root):
    found = nodes(svg_root)
    for name in ("YouBot", "Stereo", "Room", "AdditionalPC", "Mapping"):
        assert found[f"feature.{name}"].find("s:path", SVG).get("fill") == SELECTED_GREEN
    for name in ("Roomba", "Depth", "Corridor", "Logging"):
        assert found[f"feature.{name}"].find("s:path", SVG).get("fill") == "white"


def test_abstract_features_are_italic(svg_root):
    found = nodes(svg_root)
    (title,) = [t for t in found["feature.MobileBase"].iterfind(".//s:text", SVG)]
    assert title.get("font-style") == "italic"
    (concrete,) = list(found["feature.YouBot"].iterfind(".//s:text", SVG))
    assert concrete.get("font-style") is None and concrete.get("font-weight") == "bold"


def test_feature_model_notation(svg_root):
    found, lines = nodes(svg_root), edges(svg_root)
    # mandatory: filled circle at the child end, optional: hollow circle
    mandatory = lines["feature.Mapping->feature.SharedMap"].find("s:ellipse", SVG)
    optional = lines["feature.Mapping->feature.AdditionalPC"].find("s:ellipse", SVG)
    assert mandatory.get("fill") == "black" and optional.get("fill") == "none"
    # groups: a connector labelled xor / or / [n..m]; or-groups filled
    labels = {
        title: [t.text for t in g.iterfind(".//s:text", SVG)]
        for title, g in found.items()
        if title.startswith("group.")
    }
    assert labels["group.MobileBase.0"] == ["xor"]
    assert labels["group.Logging.0"] == ["or"]
    assert labels["group.Robots.0"] == ["[1..*]"]
    assert found["group.Logging.0"].find("s:polygon", SVG).get("fill") == "black"
    assert found["group.MobileBase.0"].find("s:polygon", SVG).get("fill") == "white"
    assert "group.MobileBase.0->feature.YouBot" in lines


def test_without_selection_nothing_is_green():
    graph = feature_model_graph(mapping_feature_model(), formula_text=format_formula)
    assert SELECTED_GREEN.encode() not in render_bytes(graph, "svg")
