"""Reading spl's ``.ecore`` files into pyecore packages without pyecore's XMI machinery.

Why: every ``spl`` process needs the metamodels, and pyecore's resource layer costs
more than the metamodels themselves (it imports lxml and urllib.request — with http,
email and ssl — and resolves every reference through URIs); on ``spl check`` of a
shipped line that was a sixth of the whole process. The three files use a small part
of Ecore (classes, attributes, references, enums, annotations, cross-file references
``fm.ecore#//Feature``), which this module reads with the standard library's XML parser
and builds with pyecore's own constructors. ``tests/test_metamodels.py`` checks that
the result is the same, element for element, as pyecore's XMI loader
(:func:`spl.metamodels.resource_set`).
"""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from pathlib import Path
from typing import cast

from pyecore import ecore
from pyecore.ecore import (
    EAnnotation,
    EAttribute,
    EClass,
    EEnum,
    EEnumLiteral,
    EModelElement,
    EPackage,
    EReference,
)

_XSI_TYPE = "{http://www.w3.org/2001/XMLSchema-instance}type"
_ECORE = "http://www.eclipse.org/emf/2002/Ecore"
_FEATURE_FLAGS = ("transient", "volatile", "derived", "unsettable", "ordered", "unique")


def read_packages(paths: list[Path]) -> dict[str, EPackage]:
    """The packages of the ``.ecore`` files (by file name), references across them resolved."""
    roots = {path.name: ElementTree.parse(path).getroot() for path in paths}
    packages: dict[str, EPackage] = {}
    classifiers: dict[tuple[str, str | None], object] = {}
    for file, root in roots.items():  # first every classifier, so references resolve
        package = EPackage(root.get("name"), nsURI=root.get("nsURI"), nsPrefix=root.get("nsPrefix"))
        _annotate(package, root)
        for element in root.findall("eClassifiers"):
            classifier = _classifier(element)
            package.eClassifiers.append(classifier)
            classifiers[(file, element.get("name"))] = classifier
        packages[file] = package
    for file, root in roots.items():
        for element in root.findall("eClassifiers"):
            classifier = classifiers[(file, element.get("name"))]
            if not isinstance(classifier, EClass):
                continue
            for reference in (element.get("eSuperTypes") or "").split():
                classifier.eSuperTypes.append(_resolve(reference, file, classifiers))
            for child in element.findall("eStructuralFeatures"):
                classifier.eStructuralFeatures.append(_feature(child, file, classifiers))
    return packages


def _classifier(element: ElementTree.Element) -> object:
    kind = element.get(_XSI_TYPE)
    name = element.get("name")
    if kind == "ecore:EClass":
        classifier = EClass(name, abstract=element.get("abstract") == "true")
    elif kind == "ecore:EEnum":
        classifier = EEnum(name)
        for position, literal in enumerate(element.findall("eLiterals")):
            value = int(literal.get("value", position if position == 0 else 0))
            classifier.eLiterals.append(EEnumLiteral(literal.get("name"), value=value))
    else:
        raise ValueError(f"unsupported classifier {kind} {name} in a metamodel")
    _annotate(classifier, element)
    return classifier


def _feature(element: ElementTree.Element, file: str, classifiers: dict) -> object:
    kind = element.get(_XSI_TYPE)
    name = element.get("name")
    etype = _resolve(cast(str, element.get("eType")), file, classifiers)  # every feature has one
    lower = int(element.get("lowerBound", "0"))
    upper = int(element.get("upperBound", "1"))
    if kind == "ecore:EAttribute":
        feature = EAttribute(name, etype, lower=lower, upper=upper)
        literal = element.get("defaultValueLiteral")
        if literal is not None:
            feature.defaultValueLiteral = literal
    elif kind == "ecore:EReference":
        containment = element.get("containment") == "true"
        feature = EReference(name, etype, lower=lower, upper=upper, containment=containment)
    else:
        raise ValueError(f"unsupported feature {kind} {name} in a metamodel")
    for flag in _FEATURE_FLAGS:
        value = element.get(flag)
        if value is not None:
            setattr(feature, flag, value == "true")
    _annotate(feature, element)
    return feature


def _resolve(reference: str, file: str, classifiers: dict) -> object:
    """``#//Name``, ``ecore:EClass fm.ecore#//Name`` or an Ecore data type."""
    target = reference.split()[-1]
    where, _, name = target.partition("#//")
    if where == _ECORE:
        return getattr(ecore, name)
    return classifiers[(where or file, name)]


def _annotate(owner: EModelElement, element: ElementTree.Element) -> None:
    for child in element.findall("eAnnotations"):
        annotation = EAnnotation(source=child.get("source"))
        for detail in child.findall("details"):
            annotation.details[detail.get("key")] = detail.get("value")
        owner.eAnnotations.append(annotation)
