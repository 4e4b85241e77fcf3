"""The metamodels spl builds from its .ecore files equal what pyecore's XMI loader reads.

spl reads the files with its own small reader (``spl.metamodels.ecore_files``: no XMI
resource layer at start-up); this compares every package, classifier, literal, feature
and annotation with pyecore's own reading of the same files, so the two cannot differ.
"""

from __future__ import annotations

from importlib.resources import files

import pytest
from pyecore.ecore import EClass, EEnum, EPackage
from pyecore.resources import URI, ResourceSet

from spl.metamodels import NAMES, load, packages, resource_set


def qualified(classifier) -> str | None:
    if classifier is None:
        return None
    package = classifier.ePackage
    return f"{package.name if package is not None else '?'}::{classifier.name}"


def annotations(element) -> list:
    return [(a.source, sorted(dict(a.details).items())) for a in element.eAnnotations]


def outline(package) -> list[tuple]:
    """Everything the Ecore API tells about a package, in order."""
    rows: list[tuple] = [
        ("package", package.name, package.nsURI, package.nsPrefix, annotations(package))
    ]
    for classifier in package.eClassifiers:
        if isinstance(classifier, EEnum):
            literals = [(x.name, x.value, x.literal) for x in classifier.eLiterals]
            rows.append(("enum", classifier.name, literals, annotations(classifier)))
            continue
        assert isinstance(classifier, EClass), classifier
        rows.append(
            (
                "class",
                classifier.name,
                classifier.abstract,
                [qualified(s) for s in classifier.eSuperTypes],
                sorted(qualified(s) for s in classifier.eAllSuperTypes()),
                annotations(classifier),
            )
        )
        for f in classifier.eStructuralFeatures:
            rows.append(
                (
                    type(f).__name__,
                    f.name,
                    qualified(f.eType),
                    f.lowerBound,
                    f.upperBound,
                    getattr(f, "containment", None),
                    (f.transient, f.derived, f.changeable, f.volatile, f.unsettable),
                    (f.ordered, f.unique, f.defaultValueLiteral, repr(f.get_default_value())),
                    annotations(f),
                )
            )
    return rows


@pytest.fixture(scope="module")
def by_pyecore() -> dict[str, EPackage]:
    rset = ResourceSet()
    found = {}
    for name in NAMES:
        resource = rset.get_resource(URI(str(files("spl.metamodels").joinpath(f"{name}.ecore"))))
        found[name] = resource.contents[0]
    return found


@pytest.mark.parametrize("name", NAMES)
def test_same_metamodel_as_pyecores_xmi_reader(name: str, by_pyecore: dict) -> None:
    ours = outline(packages()[name])
    theirs = outline(by_pyecore[name])
    assert len(ours) > 10
    assert ours == theirs


def test_classes_instantiate_and_cross_references_resolve() -> None:
    tsm, fm, rm = load("tsm"), load("fm"), load("rm")
    feature = fm.Feature(name="Stereo")
    element = rm.ResolutionElement(feature=feature)
    assert element.feature is feature and element.activeIfSelected is True
    assert fm.Group(kind=fm.GroupKind.alternative).kind.name == "alternative"
    node = tsm.Node(name="n")
    assert node.srcLine == 0 and isinstance(node, tsm.NamedElement)
    registry = resource_set().metamodel_registry
    assert {registry[p.nsURI].name for p in packages().values()} == set(NAMES)
