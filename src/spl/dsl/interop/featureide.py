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

from spl.core.diagnostics import Diagnostic, DiagnosticSink, Location, ModelError
from spl.dsl.fm.vocabulary import (
    SHARING_MODES,
    balanced,
    canonical_value,
    formula_too_deep,
    too_deep,
)
from spl.dsl.interop.interchange import (
    CAPABILITY,
    ORIGINAL_NAME,
    FeatureNames,
    add_capabilities,
    model_name,
)
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
        self.balance = False  # build <conj>/<disj> balanced (a constraint too deep left-deep)

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
            if refused:  # built left-deep; with its <conj>/<disj> balanced it may fit
                self.balance = True
                formula = self.formula(parts[0])
                self.balance = False
                refused = formula_too_deep(formula)
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
            name = element.text or ""
            reference = self.locate(F.FeatureRef(), element)
            # the name exactly (FeatureIDE writes it so, blanks of a name included), else
            # without the blanks a hand-written file puts around it
            target = self.features.get(name) or self.features.get(name := name.strip())
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

        def join(left: Any, right: Any) -> Any:
            binary = self.locate(F.BinaryFormula(operator=operator), element)
            binary.left, binary.right = left, right
            return binary

        if self.balance and operator in ("and", "or"):
            return balanced(parts, join)
        result = parts[0]
        for part in parts[1:]:
            result = join(result, part)
        return result


def _identifier(name: str) -> bool:
    return (
        name.isascii()
        and (name[:1].isalpha() or name[:1] == "_")
        and name.replace("_", "a").isalnum()
    )


# -- export ---------------------------------------------------------------------------
