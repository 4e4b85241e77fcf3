"""FeatureIDE XML out: a feature model written as FeatureIDE's ``model.xml`` (the reader is
:mod:`spl.dsl.interop.featureide`). Original names and capability conditions travel as the
formats' shared attributes (:mod:`spl.dsl.interop.interchange`); what FeatureIDE cannot hold
(a cardinality group it has no element for) is refused, located in the model.
"""

from __future__ import annotations

from typing import Any

from lxml import etree

from spl.core.diagnostics import Diagnostic, Location, ModelError
from spl.dsl.fm.printer import format_capabilities
from spl.dsl.interop.interchange import CAPABILITY, exported_attributes, original_name

_TYPES_OUT = {"int": "long", "double": "double", "string": "string", "bool": "boolean"}


def write_featureide(model: Any) -> bytes:
    """The model as FeatureIDE XML (UTF-8 bytes, tab-indented, deterministic)."""
    problems: list[Diagnostic] = []
    document = etree.Element("featureModel")
    etree.SubElement(document, "properties")
    struct = etree.SubElement(document, "struct")
    _write_feature(struct, model.root, False, problems)
    if model.constraints:
        constraints = etree.SubElement(document, "constraints")
        for constraint in model.constraints:
            rule = etree.SubElement(constraints, "rule")
            _write_formula(rule, constraint.formula)
    if problems:
        raise ModelError(problems)
    etree.indent(document, space="\t")
    body = etree.tostring(document, encoding="unicode")
    return (_DECLARATION + body + "\n").encode("utf-8")


_DECLARATION = '<?xml version="1.0" encoding="UTF-8" standalone="no"?>\n'


def _where(element: Any) -> Location | None:
    if not getattr(element, "srcFile", None):
        return None
    return Location(element.srcFile, element.srcLine or 0, element.srcCol or 0)


def _decomposition(feature: Any, problems: list[Diagnostic]) -> tuple[str, list[tuple[Any, bool]]]:
    """The FeatureIDE tag of a feature and its children with their mandatory flags."""
    groups = list(feature.groups)
    if not any(group.features for group in groups):
        return "feature", []
    kinds = []
    for group in groups:
        kind = group.kind.name
        if kind == "cardinality":
            size = len(group.features)
            upper = size if group.upper == -1 else min(group.upper, size)
            if group.lower == 1 and upper == 1:
                kind = "alternative"
            elif group.lower == 1 and upper == size:
                kind = "or"
            elif group.lower == 0 and upper == size:
                kind = "optional"
            elif group.lower == size and upper == size:
                kind = "mandatory"
        kinds.append(kind)
    if all(kind in ("mandatory", "optional") for kind in kinds):
        children = [
            (child, kind == "mandatory")
            for group, kind in zip(groups, kinds, strict=True)
            for child in group.features
        ]
        return "and", children
    if len(groups) == 1 and kinds[0] in ("alternative", "or") and len(groups[0].features) == 1:
        # FeatureIDE reads a one-child alt/or as an and-group: write what it means
        return "and", [(groups[0].features[0], True)]
    if len(groups) == 1 and kinds[0] in ("alternative", "or"):
        tag = "alt" if kinds[0] == "alternative" else "or"
        return tag, [(child, False) for child in groups[0].features]
    shapes = [  # as the .fm language writes them
        f"[{g.lower}..{'*' if g.upper == -1 else g.upper}]"
        if k == "cardinality"
        else {"alternative": "xor"}.get(k, k)
        for g, k in zip(groups, kinds, strict=True)
    ]
    cardinalities = [s for s, k in zip(shapes, kinds, strict=True) if k == "cardinality"]
    if cardinalities:  # no place in the tree helps: FeatureIDE has no such group
        hint = (
            f"FeatureIDE has no group cardinality {cardinalities[0]} of "
            f"{len(groups[kinds.index('cardinality')].features)} features (only alt [1..1] "
            "and or [1..n]); make it an or group with a constraint bounding how many are "
            "selected, or keep the model in .fm or UVL"
        )
    else:  # one alt/or group per feature: each of the others under a feature of its own
        hint = "move each xor/or group under an abstract feature of its own"
    problems.append(
        Diagnostic(
            _where(feature),
            f"feature {feature.name}: FeatureIDE XML cannot express its groups "
            f"({', '.join(shapes)}); {hint}",
        )
    )
    return "and", []


def _write_feature(parent: Any, feature: Any, mandatory: bool, problems: list) -> None:
    tag, children = _decomposition(feature, problems)
    attributes: dict[str, str] = {}
    if feature.abstract:
        attributes["abstract"] = "true"
    if mandatory:
        attributes["mandatory"] = "true"
    attributes["name"] = original_name(feature)
    try:
        element = etree.SubElement(parent, tag, attributes)
    except ValueError:
        problems.append(
            Diagnostic(
                _where(feature), f"feature name {attributes['name']!r} cannot be written in XML"
            )
        )
        return
    for attribute in exported_attributes(feature):
        etree.SubElement(
            element,
            "attribute",
            {
                "name": attribute.name,
                "type": _TYPES_OUT[attribute.type.name],
                "value": attribute.value or "",
            },
        )
    if feature.sharing is not None:
        etree.SubElement(
            element,
            "attribute",
            {"name": "sharing", "type": "string", "value": feature.sharing.mode.name},
        )
    if feature.capabilities:
        etree.SubElement(
            element,
            "attribute",
            {"name": CAPABILITY, "type": "string", "value": format_capabilities(feature)},
        )
    for child, child_mandatory in children:
        _write_feature(element, child, child_mandatory, problems)


def _write_formula(parent: Any, formula: Any) -> None:
    kind = formula.eClass.name
    if kind == "FeatureRef":
        etree.SubElement(parent, "var").text = original_name(formula.feature)
        return
    if kind == "Not":
        _write_formula(etree.SubElement(parent, "not"), formula.operand)
        return
    operator = formula.operator
    tag = {"and": "conj", "or": "disj", "implies": "imp", "iff": "eq"}.get(operator, "imp")
    element = etree.SubElement(parent, tag)
    _write_formula(element, formula.left)
    if operator == "excludes":
        _write_formula(etree.SubElement(element, "not"), formula.right)
    else:
        _write_formula(element, formula.right)
