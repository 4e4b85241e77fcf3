"""FeatureIDE XML import and export (``<featureModel><struct>...<constraints>``), with lxml.

FeatureIDE gives each feature one decomposition: ``and`` (children each mandatory or
optional), ``or`` or ``alt``; like FeatureIDE itself, an ``or``/``alt`` with a single
child is read as an ``and`` (the child's ``mandatory`` flag decides). Reading, an
``and`` becomes one group per run of consecutive children with the same
``mandatory`` flag, so document order survives a round trip. Writing, a feature must
fit one decomposition: mandatory/optional groups only, or one xor/or group;
cardinality groups are written when FeatureIDE can express them (``[1..1]`` as alt,
``[1..*]`` as or, ``[0..*]`` as optional children) and other shapes are reported
instead of being approximated. Feature attributes use the extended-feature-model
``<attribute name type value/>`` element; the sharing mode is an attribute
``sharing``; ``requires``/``excludes`` become ``imp`` (with ``not``).

Input is hostile: entities are not resolved and nothing is fetched from the network.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from lxml import etree

from spl.diagnostics import Diagnostic, DiagnosticSink, Location, ModelError
from spl.dsl.fm_interchange import (
    CAPABILITY,
    ORIGINAL_NAME,
    FeatureNames,
    add_capabilities,
    exported_attributes,
    model_name,
    original_name,
)
from spl.dsl.fm_printer import format_capabilities
from spl.dsl.fm_vocabulary import SHARING_MODES, canonical_value, formula_too_deep, too_deep
from spl.metamodels import fm as fm_metamodel

_FEATURE_TAGS = {"feature", "and", "or", "alt"}
_TYPES_IN = {
    "long": "int",
    "int": "int",
    "integer": "int",
    "double": "double",
    "float": "double",
    "string": "string",
    "boolean": "bool",
    "bool": "bool",
}
_TYPES_OUT = {"int": "long", "double": "double", "string": "string", "bool": "boolean"}


def _parser() -> etree.XMLParser:
    return etree.XMLParser(
        resolve_entities=False, no_network=True, load_dtd=False, remove_comments=True
    )


def read_featureide(path: str | Path) -> Any:
    """Import a FeatureIDE XML feature model; raise ModelError with every problem."""
    path = Path(path)
    return parse_featureide(path.read_bytes(), str(path), default_name=path.stem)


def parse_featureide(
    data: bytes, filename: str = "<string>", default_name: str = "FeatureModel"
) -> Any:
    """Import FeatureIDE XML bytes; the model is named ``default_name`` (the file stem)."""
    try:
        document = etree.fromstring(data, _parser())
    except etree.XMLSyntaxError as exc:
        line, col = exc.position if exc.position else (0, 0)
        message = str(exc.msg).split(", line ")[0]
        where = Location(filename, line, col)
        raise ModelError([Diagnostic(where, f"XML syntax error: {message}")]) from None
    try:
        return _Reader(filename).read(document, default_name)
    except RecursionError:
        raise ModelError([too_deep(filename)]) from None


class _Reader:
    def __init__(self, filename: str) -> None:
        self.filename = filename
        self.sink = DiagnosticSink()
        self.F = fm_metamodel()
        self.features: dict[str, Any] = {}

    def loc(self, element: Any) -> Location:
        return Location(self.filename, element.sourceline or 0, 1)

    def locate(self, model_element: Any, element: Any) -> Any:
        where = self.loc(element)
        model_element.srcFile, model_element.srcLine = where.file, where.line
        model_element.srcCol = where.col
        return model_element

    def error(self, element: Any, message: str) -> None:
        self.sink.error(self.loc(element), message)

    def flag(self, element: Any, name: str) -> bool:
        """A boolean attribute (xs:boolean: true, false, 1, 0; absent is false). Anything
        else is an error: read as false it silently changed the model (``mandatory="yes"``
        made a mandatory feature optional)."""
        text = element.get(name)
        if text is None or text in ("false", "0"):
            return False
        if text not in ("true", "1"):
            self.error(element, f'{name}="{text}": expected true or false')
        return text in ("true", "1")

    def read(self, document: Any, default_name: str) -> Any:
        F = self.F
        if document.tag not in ("featureModel", "extendedFeatureModel"):
            self.error(document, f"expected <featureModel>, got <{document.tag}>")
            self.sink.raise_if_errors()
        model = self.locate(F.FeatureModel(name=model_name(default_name)), document)
        struct = document.find("struct")
        roots = [] if struct is None else [e for e in struct if e.tag in _FEATURE_TAGS]
        if not roots:
            self.error(document if struct is None else struct, "no <struct> with a root feature")
            self.sink.raise_if_errors()
        for extra in roots[1:]:
            self.error(extra, "a feature model has exactly one root feature")
        names = [e.get("name") for e in roots[0].iter(*_FEATURE_TAGS)]
        self.names = FeatureNames(name for name in names if name)
        model.root = self.feature(roots[0])
        constraints = document.find("constraints")
        for rule in [] if constraints is None else constraints.iter("rule"):
            parts = [e for e in rule if isinstance(e.tag, str) and e.tag != "description"]
            if len(parts) != 1:
                self.error(rule, "a <rule> holds exactly one formula")
                continue
            formula = self.formula(parts[0])
            refused = formula_too_deep(formula) if formula is not None else None
            if refused:
                self.error(rule, refused)
            elif formula is not None:
                constraint = self.locate(F.Constraint(), rule)
                constraint.formula = formula
                model.constraints.append(constraint)
        self.sink.raise_if_errors()
        return model

    def feature(self, element: Any) -> Any:
        F = self.F
        original = element.get("name")
        if not original:
            self.error(element, f"<{element.tag}> without a name")
            return self.locate(F.Feature(name="_"), element)
        identifier = self.names[original]
        feature = self.locate(F.Feature(name=identifier), element)
        feature.abstract = self.flag(element, "abstract")
        if original in self.features:
            self.error(element, f"duplicate feature {original}")
        else:
            self.features[original] = feature
        if identifier != original:
            kept = self.locate(F.Attribute(name=ORIGINAL_NAME, value=original), element)
            kept.type = F.AttributeType.string
            feature.attributes.append(kept)
        for attribute_element in element.findall("attribute"):
            self.attribute(feature, attribute_element)
        children = [e for e in element if e.tag in _FEATURE_TAGS]
        if element.tag == "feature" and children:
            self.error(children[0], "a <feature> cannot have child features (use <and>)")
            return feature
        if not children:
            return feature
        if element.tag in ("or", "alt") and len(children) > 1:
            group = self.locate(F.Group(), element)
            group.kind = F.GroupKind.getEEnumLiteral("or" if element.tag == "or" else "alternative")
            group.features.extend(self.feature(child) for child in children)
            feature.groups.append(group)
            return feature
        group = None
        for child in children:
            kind = "mandatory" if self.flag(child, "mandatory") else "optional"
            if group is None or group.kind.name != kind:
                group = self.locate(F.Group(), child)
                group.kind = F.GroupKind.getEEnumLiteral(kind)
                feature.groups.append(group)
            group.features.append(self.feature(child))
        return feature

    def attribute(self, feature: Any, element: Any) -> None:
        F = self.F
        name, type_text, value = element.get("name"), element.get("type"), element.get("value")
        type_name = _TYPES_IN.get((type_text or "").lower())
        if not name or type_name is None or value is None:
            self.error(element, "an <attribute> needs a name, a known type and a value")
            return
        if name == ORIGINAL_NAME:
            self.error(element, f"attribute name {ORIGINAL_NAME} is reserved")
            return
        if name == "sharing":
            if type_name != "string" or value not in SHARING_MODES or feature.sharing is not None:
                self.error(element, f"sharing must be one of {', '.join(SHARING_MODES)}")
                return
            config = self.locate(F.SharingConfig(), element)
            config.mode = F.SharingMode.getEEnumLiteral(value)
            feature.sharing = config
            return
        if name == CAPABILITY:
            try:
                add_capabilities(feature, type_name, value, self.loc(element))
            except ModelError as exc:
                self.sink.diagnostics.extend(exc.diagnostics)
            return
        if not _identifier(name):
            self.error(element, f"attribute name {name!r} is not an identifier")
            return
        canonical = canonical_value(type_name, value)
        if canonical is None:
            self.error(element, f"attribute {name}: {value!r} is not a {type_name}")
            return
        attribute = self.locate(F.Attribute(name=name, value=canonical), element)
        attribute.type = F.AttributeType.getEEnumLiteral(type_name)
        feature.attributes.append(attribute)

    def formula(self, element: Any) -> Any:
        F = self.F
        tag = element.tag
        operands = [e for e in element if isinstance(e.tag, str)]
        if tag == "var":
            name = (element.text or "").strip()
            reference = self.locate(F.FeatureRef(), element)
            target = self.features.get(name)
            if target is None:
                self.error(element, f"unknown feature {name}")
                return None
            reference.feature = target
            return reference
        if tag == "not":
            if len(operands) != 1:
                self.error(element, "<not> takes exactly one operand")
                return None
            inner = self.formula(operands[0])
            if inner is None:
                return None
            negation = self.locate(F.Not(), element)
            negation.operand = inner
            return negation
        operator = {"imp": "implies", "eq": "iff", "conj": "and", "disj": "or"}.get(tag)
        if operator is None:
            self.error(element, f"unsupported constraint element <{tag}>")
            return None
        if (tag in ("imp", "eq") and len(operands) != 2) or not operands:
            self.error(element, f"<{tag}> has {len(operands)} operands")
            return None
        parts = [self.formula(operand) for operand in operands]
        if any(part is None for part in parts):
            return None
        result = parts[0]
        for part in parts[1:]:
            binary = self.locate(F.BinaryFormula(operator=operator), element)
            binary.left, binary.right = result, part
            result = binary
        return result


def _identifier(name: str) -> bool:
    return (
        name.isascii()
        and (name[:1].isalpha() or name[:1] == "_")
        and name.replace("_", "a").isalnum()
    )


# -- export ---------------------------------------------------------------------------
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
