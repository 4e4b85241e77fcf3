"""The .tsm metamodel as plain Python classes, for checks that need no pyecore model.

Why: the builder (``spl.dsl.tsm.language``) spends most of its time in pyecore on a big file
(a 10,000-node .tsm sets some 400,000 features, each through pyecore's descriptors,
type checks and notifications), yet ``spl check FILE.tsm`` and the editor's
diagnostics only need the problems the builder finds. These classes are generated
from ``src/spl/metamodels/tsm.ecore`` so they cannot drift from it: one class per EClass with
every feature of the class and its supertypes under the metamodel's names and
pyecore's default values, ``eClass`` (the very EClass, so ``eClass.name`` reads the
same), ``eContainer()``, ``eGet``/``eSet``, containment that sets the container (a
list for a many-valued feature, a property for a single one), and the metamodel's
own enum literals. The metamodel declares no eOpposite, so no reference has a
counterpart to keep in step. The builder runs unchanged over them
(``tests/dsl/test_tsm_plain.py`` compares the diagnostics of both builds), and
``spl.dsl.tsm.language.parse_text`` builds over them too, then copies the checked model into
pyecore in one pass (``spl.core.emf.copy_model`` reads plain elements as it reads pyecore
objects), which costs half of building through pyecore.
"""

from __future__ import annotations

import weakref
from collections.abc import Iterable
from functools import cache
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any, cast

from pyecore.ecore import EClass, EEnum, EReference

from spl.metamodels import tsm as tsm_metamodel

if TYPE_CHECKING:
    from spl.metamodels import tsm_types


class PlainElement:
    """What every plain model element answers like a pyecore object.

    The container is held by a weak reference, so a model holds no reference cycle and
    is freed as soon as its last user lets it go (the editor checks a 10,000-node file
    on every change: cyclic garbage of 100,000 objects a check made the collector's
    full passes cost seconds). ``eContainer()`` answers while the model's root lives."""

    __slots__ = ("__weakref__", "_container")
    _container: weakref.ref[PlainElement] | None  # (a slot)
    eClass: Any = None

    def eContainer(self) -> Any:  # the metamodel API's spelling
        container = self._container
        return container() if container is not None else None

    def eGet(self, feature: Any) -> Any:
        return getattr(self, feature if isinstance(feature, str) else feature.name)

    def eSet(self, feature: Any, value: Any) -> None:
        setattr(self, feature if isinstance(feature, str) else feature.name, value)

    def __repr__(self) -> str:
        return f"<plain {self.eClass.name} {getattr(self, 'name', '')!r}>"


class Contained(list):
    """A many-valued containment: every element added gets its owner as container."""

    __slots__ = ("owner",)

    def __init__(self, owner: PlainElement) -> None:
        super().__init__()
        self.owner = weakref.ref(owner)

    def append(self, element: Any) -> None:
        element._container = self.owner
        list.append(self, element)

    def insert(self, index: Any, element: Any) -> None:
        element._container = self.owner
        list.insert(self, index, element)

    def extend(self, elements: Iterable[Any]) -> None:
        for element in elements:
            self.append(element)

    def __iadd__(self, elements: Iterable[Any]) -> Contained:  # type: ignore[misc]
        self.extend(elements)
        return self

    def __setitem__(self, index: Any, value: Any) -> None:
        for element in value if isinstance(index, slice) else (value,):
            element._container = self.owner
        list.__setitem__(self, index, value)


LOCATION = ("srcFile", "srcLine", "srcCol")


def _location_property(index: int) -> property:
    """``srcFile``, ``srcLine`` or ``srcCol``, worked out from the stored position when
    first read: a check builds some 30,000 located elements of a 10,000-node file and
    reads the place of a handful (those with problems); the editor reads them later."""

    def get(self: Any) -> Any:
        where = self._location
        if len(where) == 2:  # (names, parse tree): not worked out yet
            where = self._location = where[0].place(where[1])
        return where[index]

    def set_(self: Any, value: Any) -> None:
        where = self._location
        if len(where) == 2:
            where = where[0].place(where[1])
        self._location = (*where[:index], value, *where[index + 1 :])

    return property(get, set_)


def _contained_property(slot: str) -> property:
    """A single-valued containment: the element set gets its owner as container."""

    def get(self: Any) -> Any:
        return getattr(self, slot)

    def set_(self: Any, value: Any) -> None:
        if value is not None:
            value._container = weakref.ref(self)
        setattr(self, slot, value)

    return property(get, set_)


def _plain_class(eclass: EClass) -> type:
    """The plain class of ``eclass``: generated ``__init__`` taking any feature by
    keyword, each feature starting at pyecore's default."""
    defaults: dict[str, Any] = {}
    source = ["def __init__(self, **given):", "    self._container = None"]
    slots: list[str] = []
    members: dict[str, Any] = {"__slots__": (), "eClass": eclass}
    sample = None if eclass.abstract else eclass.python_class()
    for feature in eclass.eAllStructuralFeatures():
        name = feature.name
        if name in LOCATION:  # see _location_property
            if "_location" not in slots:
                slots.append("_location")
                source.append("    self._location = (None, 0, 0)")
            members[name] = _location_property(LOCATION.index(name))
            continue
        containment = isinstance(feature, EReference) and feature.containment
        if feature.many:
            slots.append(name)
            made = "Contained(self)" if containment else "[]"
            source.append(f"    self.{name} = {made}")
            source.append(f"    if {name!r} in given: self.{name}.extend(given.pop({name!r}))")
        elif containment:
            slot = f"_contained_{name}"
            slots.append(slot)
            members[name] = _contained_property(slot)
            source.append(f"    self.{slot} = None")
        else:
            slots.append(name)
            defaults[name] = getattr(sample, name) if sample is not None else None
            source.append(f"    self.{name} = DEFAULTS[{name!r}]")
    source.append("    for key, value in given.items(): setattr(self, key, value)")
    namespace: dict[str, Any] = {"Contained": Contained, "DEFAULTS": defaults}
    exec("\n".join(source), namespace)  # the source is made of metamodel names only
    members["__slots__"] = tuple(slots)
    members["__init__"] = namespace["__init__"]
    return type(eclass.name, (PlainElement,), members)


@cache
def metamodel() -> tsm_types.Metamodel:
    """The .tsm metamodel as plain classes, shaped like :func:`spl.metamodels.tsm`:
    ``metamodel().Node(name=...)``, ``metamodel().SharingMode.private``; its elements
    take a location to work out when read (``located_later``)."""
    ecore = tsm_metamodel()
    members: dict[str, Any] = {"package": ecore.package, "located_later": True}
    for classifier in ecore.package.eClassifiers:
        if isinstance(classifier, EClass):
            members[classifier.name] = _plain_class(classifier)
        elif isinstance(classifier, EEnum):
            members[classifier.name] = classifier  # the same literals as the pyecore model
    return cast("tsm_types.Metamodel", SimpleNamespace(**members))  # as tsm() gives it
