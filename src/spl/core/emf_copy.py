"""Copying pyecore models: a tree read once, as an image, then written out as often as
asked.

Why an image: the Resolution Engine copies a line's template for every product it
resolves (docs/resolution.md, step 2), and the line checks resolve dozens of witness
products of one line (docs/performance.md, "Large product lines"). Reading the template
through pyecore's descriptors, feature by feature, unset ones included, was half of each
copy; the image reads it once (``ProductLine.template_image``,
:mod:`spl.resolver.resolution.product_line`) and keeps, per element, only what a copy
sets. Writing sets each slot as pyecore would, without its per-value type check and
notification: the values come from the same features of the original, and nobody
listens to a copy being built.
"""

from __future__ import annotations

from collections.abc import Callable, Container
from typing import Any

from ordered_set import OrderedSet
from pyecore.ecore import EAttribute, EObject, EReference, EStructuralFeature
from pyecore.innerutils import InternalSet
from pyecore.valuecontainer import EBag, EList, EOrderedSet, ESet, EValue

_FEATURES: dict[int, tuple] = {}
_PLANS: dict[int, tuple] = {}
_NAMES: dict[int, str] = {}  # each class's name, with its plan (pyecore reads it slowly)


def all_features(obj: EObject) -> tuple:
    """All structural features of the object's class, computed once per class
    (pyecore rebuilds the ordered set on every call, which dominated copying)."""
    eclass = obj.eClass
    features = _FEATURES.get(id(eclass))
    if features is None:
        features = _FEATURES[id(eclass)] = (eclass, tuple(eclass.eAllStructuralFeatures()))
    return features[1]


def plan(obj: EObject) -> tuple[tuple, tuple]:
    """Per class: (name, many, containment, default, feature) of values to copy, then
    (name, many, feature) of references; the feature only where the copy sets it
    directly (:func:`_direct`), else None."""
    eclass = obj.eClass
    found = _PLANS.get(id(eclass))
    if found is None:
        values, references = [], []
        for feature in all_features(obj):
            if isinstance(feature, EAttribute):
                default = None if feature.many else feature.get_default_value()
                values.append((feature.name, feature.many, False, default, _direct(feature)))
            elif feature.containment:
                values.append((feature.name, feature.many, True, None, _direct(feature)))
            else:
                references.append((feature.name, feature.many, _direct(feature)))
        found = _PLANS[id(eclass)] = (eclass, tuple(values), tuple(references))
        _NAMES[id(eclass)] = eclass.name
    return found[1], found[2]


def class_name(obj: EObject) -> str:
    """The name of the object's class, known once :func:`plan` read the class."""
    return _NAMES[id(obj.eClass)]


# What an element of an image sets, in its class's order of features: a single value,
# the values of a many-valued attribute, one contained element, contained elements.
_VALUE, _VALUES, _CHILD, _CHILDREN = range(4)
# An element of an image: the original, its Python class, whether pyecore made that
# class from the EClass (:func:`new_element`), the features its copy marks set at once,
# its single attributes set at once, what else it sets, its references.
Entry = tuple[EObject, type, bool, dict, tuple, tuple, tuple]


class TreeImage:
    """The containment trees under ``roots``, read once, for :meth:`copy`."""

    def __init__(self, roots: list[EObject]) -> None:
        self.roots = [_read(root) for root in roots]

    def copy(
        self,
        outside: Callable[[EObject], EObject] | None = None,
        left_out: Container[int] = (),
    ) -> tuple[list[EObject], dict[int, EObject]]:
        """Deep copies of the trees, each reference to an element of one of them
        remapped to its copy, each other one to what ``outside`` gives for its target
        (kept without ``outside``); with the map ``id(original) -> copy``. The members
        of collections ``left_out`` (by id) are not copied, nor what they hold. A
        default value is not set again."""
        mapping: dict[int, EObject] = {}
        pending: list[tuple[EObject, tuple]] = []

        def clone(entry: Entry) -> EObject:
            src, python_class, generated, marks, attributes, sets, references = entry
            dst = new_element(python_class) if generated else python_class()
            mapping[id(src)] = dst
            if references:
                pending.append((dst, references))
            if marks:
                dst._isset.update(marks)
            if attributes:
                _set_attributes(dst, attributes)
            for kind, name, feature, value in sets:
                if kind is _CHILDREN:
                    items = [clone(c) for key, c in value if key not in left_out]
                    if feature is not None:
                        extend(dst, feature, name, items, True)
                    else:
                        getattr(dst, name).extend(items)
                elif kind is _CHILD:
                    if feature is not None:
                        _set_reference(dst, feature, name, clone(value), True)
                    else:
                        setattr(dst, name, clone(value))
                elif kind is _VALUE:
                    if feature is not None:
                        _set_attribute(dst, feature, name, value)
                    else:
                        setattr(dst, name, value)
                elif feature is not None:
                    extend(dst, feature, name, value, False)
                else:
                    getattr(dst, name).extend(value)
            return dst

        def mapped(value: EObject) -> EObject:
            found = mapping.get(id(value))
            if found is not None:
                return found
            return outside(value) if outside is not None else value

        copies = [clone(root) for root in self.roots]
        for dst, references in pending:
            for name, many, feature, value in references:
                if many:
                    items = [mapped(v) for v in value]
                    if feature is not None:
                        extend(dst, feature, name, items, False)
                    else:
                        getattr(dst, name).extend(items)
                elif feature is not None:
                    _set_reference(dst, feature, name, mapped(value), False)
                else:
                    setattr(dst, name, mapped(value))
        # clone refers to itself through its closure, a cycle the collector alone breaks:
        # what it holds must not be the copy's elements, which a caller done with the
        # copy releases (Resolution.release; a 10,000-node line's witness products)
        pending.clear()
        return copies, mapping


def _read(src: EObject) -> Entry:
    """The image of ``src`` and what it contains: what a copy of each sets."""
    values, references = plan(src)
    state = getattr(src, "__dict__", None)  # none: a plain element (spl.dsl.tsm.plain)
    sets: list[tuple[int, str, EStructuralFeature | None, Any]] = []
    for name, many, containment, default, feature in values:
        if many or state is None:
            value = getattr(src, name)
        else:  # read as pyecore's descriptor does, without the descriptor call
            slot = state.get(name)
            if slot is None:  # never set nor read: the default, not copied
                continue
            value = slot._value if type(slot) is EValue else getattr(src, name)
        if many:
            if value and containment:
                sets.append((_CHILDREN, name, feature, tuple((id(c), _read(c)) for c in value)))
            elif value:
                sets.append((_VALUES, name, feature, tuple(value)))
        elif value is None or value == default:
            continue
        elif containment:
            sets.append((_CHILD, name, feature, _read(value)))
        else:
            sets.append((_VALUE, name, feature, value))
    found = []
    for name, many, feature in references:
        value = getattr(src, name)
        if many and value:
            found.append((name, True, feature, tuple(value)))
        elif not many and value is not None:
            found.append((name, False, feature, value))
    python_class = src.eClass.python_class
    generated = (
        python_class.__new__ is EObject.__new__
        and getattr(python_class.__init__, "__qualname__", None) == _GENERATED_INIT
    )
    if any(feature is None for _, _, feature, _ in sets):  # pyecore marks those: in order
        return src, python_class, generated, {}, (), tuple(sets), tuple(found)
    # all set directly: the features marked set at once, in the class's order (which
    # resolved.xmi follows), the single attributes in one pass
    marks = dict.fromkeys(feature for _, _, feature, _ in sets)
    attributes = tuple((name, f, value) for kind, name, f, value in sets if kind is _VALUE)
    rest = tuple(op for op in sets if op[0] is not _VALUE)
    return src, python_class, generated, marks, attributes, rest, tuple(found)


# The fields EValue(owner, attribute) sets besides owner, feature and _value, which are
# the same for every attribute (it is no reference, its type found on first check):
# filled in directly, since its __init__ (with a default value computed only to be
# replaced) was half of setting an attribute in a copy. tests/dsl/test_emf_copy.py
# checks the slots equal to pyecore's own.
_new_slot = object.__new__


def _set_attribute(obj: EObject, attribute: EAttribute, name: str, value: object) -> None:
    """``obj.name = value`` for a single-valued attribute of an object just created and
    not yet contained anywhere, as pyecore stores it: the value comes from the same
    attribute of the original (so it has the type), and nobody can listen to the new
    object yet, so pyecore's type check and notification (which walks up to the
    object's resource every time) have nothing to do; they were a third of a copy."""
    _set_attributes(obj, ((name, attribute, value),))


def _set_attributes(obj: EObject, attributes: tuple) -> None:
    """:func:`_set_attribute` for each of ``attributes`` (name, attribute, value), in
    one pass: most of a copy's slots."""
    state = obj.__dict__
    isset = obj._isset
    new = _new_slot
    for name, attribute, value in attributes:
        slot = new(EValue)
        slot.__dict__ = {
            "owner": obj,
            "feature": attribute,
            "is_ref": False,
            "is_cont": False,
            "generic_type": None,
            "_value": value,
        }
        state[name] = slot
        isset[attribute] = None


def new_element(python_class: type) -> EObject:
    """``python_class()`` for a class pyecore made from an EClass, as pyecore's
    ``EObject.__new__`` leaves it (its own state; known to its class's instances),
    without the calls around it: an element of a copy is made thousands of times a
    resolution. tests/dsl/test_emf_copy.py checks the state equal to pyecore's own."""
    obj: EObject = _new_object(python_class)
    obj.__dict__ = {
        "_internal_id": None,
        "_isset": InternalSet(),
        "_container": None,
        "_containment_feature": None,
        "_eresource": None,
        "listeners": [],
        "_eternal_listener": [],
        "_inverse_rels": set(),
        "_staticEClass": False,
        "dyn_inst": obj,
    }
    _known(obj)
    return obj


_new_object = object.__new__
_known = EObject._instances.add
# the __init__ pyecore gives a class it makes from an EClass (setting keyword arguments
# only): an element of such a class is what :func:`new_element` makes
_GENERATED_INIT = "EClass.__new__.<locals>.new_init"


def _direct(feature: EStructuralFeature) -> EStructuralFeature | None:
    """The feature when a copy sets it directly (:func:`_set_attribute`,
    :func:`_set_reference`, :func:`extend`): an attribute or a reference without an
    opposite, not derived; None when pyecore's descriptor sets it."""
    if feature.derived or (not isinstance(feature, EAttribute) and feature.eOpposite):
        return None
    return feature


def extend(
    obj: EObject, feature: EStructuralFeature, name: str, values: list, containment: bool
) -> None:
    """``getattr(obj, name).extend(values)`` for a many-valued feature of an object of a
    copy being built, as pyecore's ``extend`` leaves it (the values in the collection,
    the feature marked set, each value's container for a containment and inverse
    relation for a reference), without its type check per value and notification (the
    values are those, or the copies of those, of the original's same feature)."""
    collection = getattr(obj, name)  # created empty by pyecore, of the feature's kind
    kind = type(collection)
    if kind is EOrderedSet or kind is ESet:
        add = OrderedSet.add
        for value in values:
            add(collection, value)
    elif kind is EList or kind is EBag:
        list.extend(collection, values)
    else:
        collection.extend(values)
        return
    if feature.is_reference:
        couple = (obj, feature)
        for value in values:
            if containment:
                value._container = obj
                value._containment_feature = feature
            value._inverse_rels.add(couple)
    obj._isset[feature] = None


def _set_reference(
    obj: EObject, reference: EReference, name: str, value: EObject, containment: bool
) -> None:
    """``obj.name = value`` for a single-valued reference without an opposite, on an
    object of a copy being built, as pyecore's ``EValue._set`` leaves it (the slot, the
    feature marked set, the value's container for a containment, the value's inverse
    relation), without its type check and notification: the value is the copy of, or
    the same as, the original's value of the same feature, and the new object has no
    listener and no resource yet (as in :func:`_set_attribute`)."""
    slot = _new_slot(EValue)
    slot.__dict__ = {
        "owner": obj,
        "feature": reference,
        "is_ref": True,
        "is_cont": containment,
        "generic_type": None,
        "_value": value,
    }
    obj.__dict__[name] = slot
    obj._isset[reference] = None
    if containment:
        value._container = obj
        value._containment_feature = reference
    inverse = getattr(value, "_inverse_rels", None)
    if inverse is not None:
        inverse.add((obj, reference))
