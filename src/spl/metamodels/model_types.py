"""What the typed metamodel modules (``tsm_types``, ``fm_types``, ``rm_types``) stand on.

The classes of spl's models are made at run time from the ``.ecore`` files (pyecore's
dynamic classes, or the plain twins of :mod:`spl.dsl.tsm.plain`), so a type checker
cannot see them. ``scripts/ecore_types.py`` writes one module per metamodel declaring
every metaclass with its features as a static class; this module holds what they share:
the element base (the part of pyecore's ``EObject`` spl uses), many-valued features,
enum literals and the metaclass seen through ``eClass``.

For the type checker only: import this module and the generated ones under
``if TYPE_CHECKING:`` (nothing here exists at run time as a model class; an
``isinstance`` check takes the class from the metamodel, ``spl.metamodels.tsm().Node``).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any, Protocol, SupportsIndex, TypeVar, overload

T = TypeVar("T")


class Many(Protocol[T]):
    """A many-valued feature: pyecore's ordered collections, the plain twins' lists."""

    def __iter__(self) -> Iterator[T]: ...

    def __len__(self) -> int: ...

    def __contains__(self, element: object, /) -> bool: ...

    @overload
    def __getitem__(self, index: SupportsIndex, /) -> T: ...

    @overload
    def __getitem__(self, index: slice, /) -> Any: ...

    def append(self, element: T, /) -> None: ...

    def extend(self, elements: Iterable[T], /) -> None: ...

    def insert(self, index: int, element: T, /) -> None: ...

    def remove(self, element: T, /) -> None: ...

    def index(self, element: T, /) -> int: ...

    def clear(self) -> None: ...


class EStructuralFeature(Protocol):
    """An attribute or a reference of a metaclass (pyecore's ``EStructuralFeature``)."""

    name: str
    many: bool
    lowerBound: int
    upperBound: int
    eType: Any


class EPackage(Protocol):
    name: str
    nsURI: str
    nsPrefix: str
    eClassifiers: Many[Any]


class EClass(Protocol):
    """The metaclass of an element (``element.eClass``): pyecore's ``EClass``."""

    name: str
    abstract: bool
    ePackage: EPackage
    eStructuralFeatures: Many[EStructuralFeature]
    eSuperTypes: Many[EClass]
    python_class: type

    def eAllStructuralFeatures(self) -> Iterable[EStructuralFeature]: ...

    def findEStructuralFeature(self, name: str) -> EStructuralFeature | None: ...


class EnumLiteral:
    """A literal of an ``EEnum`` (the value of an enum attribute, ``node.sharing``)."""

    name: str
    value: int


class EnumType:
    """An ``EEnum``: its literals by name (``tsm().SharingMode.private``)."""

    name: str
    eLiterals: Many[EnumLiteral]

    def getEEnumLiteral(self, name: str) -> EnumLiteral | None: ...


class EObject:
    """A model element: the part of pyecore's ``EObject`` spl uses, answered alike by
    pyecore's objects and the plain twins."""

    eClass: EClass

    def __init__(self, **features: Any) -> None: ...

    def eContainer(self) -> EObject | None:
        """The element holding this one (None for a root, or one taken out of its model)."""
        ...

    def eGet(self, feature: str | EStructuralFeature) -> Any: ...

    def eSet(self, feature: str | EStructuralFeature, value: object) -> None: ...

    def eIsSet(self, feature: str | EStructuralFeature) -> bool: ...

    def eAllContents(self) -> Iterator[EObject]: ...

    def eContents(self) -> list[EObject]: ...

    def delete(self, recursive: bool = True) -> None: ...
