"""Generic operations on pyecore models that pyecore itself lacks.

The Resolution Engine transforms a *copy* of the template model (docs/resolution.md, step 2),
and printers are tested with parse(print(m)) == m; both need a structural view of a
model driven by its metamodel rather than by hand-written per-class code.
Transient features (source locations) are ignored by comparison but kept by copies,
so errors in a resolved model still point into the original file.
"""

from __future__ import annotations

from collections.abc import Callable, Container, Iterator
from typing import Any

from ordered_set import OrderedSet
from pyecore.ecore import EAttribute, EObject, EReference, EStructuralFeature
from pyecore.valuecontainer import EBag, EList, EOrderedSet, ESet, EValue

_FEATURES: dict[int, tuple] = {}
_PLANS: dict[int, tuple] = {}
_NAMES: dict[int, str] = {}  # each class's name, with its plan (pyecore reads it slowly)


def remove_all(collection: Any, values: list[EObject]) -> None:
    """``collection.remove(v)`` for each of ``values``, in time linear in the collection:
    pyecore's ordered sets renumber every later member on each removal (quadratic)."""
    if len(values) < 8:  # the usual few: as pyecore does it
        for value in values:
            collection.remove(value)
        return
    gone = {id(value) for value in values}
    kept = [member for member in collection if id(member) not in gone]
    collection.clear()  # every member's container unset, then set again for the kept
    collection.extend(kept)


def all_features(obj: EObject) -> tuple:
    """All structural features of the object's class, computed once per class
    (pyecore rebuilds the ordered set on every call, which dominated copying)."""
    eclass = obj.eClass
    features = _FEATURES.get(id(eclass))
    if features is None:
        features = _FEATURES[id(eclass)] = (eclass, tuple(eclass.eAllStructuralFeatures()))
    return features[1]


def _plan(obj: EObject) -> tuple[tuple, tuple]:
    """Per class: (name, many, containment, default, feature) of values to copy, then
    (name, many, feature) of references; the feature only where the copy sets it
    directly (:func:`_direct`), else None."""
    eclass = obj.eClass
    plan = _PLANS.get(id(eclass))
    if plan is None:
        values, references = [], []
        for feature in all_features(obj):
            if isinstance(feature, EAttribute):
                default = None if feature.many else feature.get_default_value()
                values.append((feature.name, feature.many, False, default, _direct(feature)))
            elif feature.containment:
                values.append((feature.name, feature.many, True, None, _direct(feature)))
            else:
                references.append((feature.name, feature.many, _direct(feature)))
        plan = _PLANS[id(eclass)] = (eclass, tuple(values), tuple(references))
        _NAMES[id(eclass)] = eclass.name
    return plan[1], plan[2]


def copy_model(root: EObject) -> EObject:
    """Deep copy of the containment tree under ``root``; references inside it are remapped."""
    return copy_with_map(root)[0]


def copy_with_map(
    root: EObject, left_out: Container[int] = ()
) -> tuple[EObject, dict[int, EObject]]:
    """Like :func:`copy_model` (but ``left_out``, see :func:`copy_trees`), with the map
    ``id(original) -> copy``: a model referring into the original (a resolution model into
    its template) finds its elements in the copy. A default value is not set again."""
    copies, mapping = copy_trees([root], left_out=left_out)
    return copies[0], mapping


def copy_trees(
    roots: list[EObject],
    outside: Callable[[EObject], EObject] | None = None,
    left_out: Container[int] = (),
) -> tuple[list[EObject], dict[int, EObject]]:
    """Deep copies of the trees under ``roots``, each reference to an element of one of
    them remapped to its copy, each other one to what ``outside`` gives for its target
    (kept without ``outside``); with the map of :func:`copy_with_map`. The template
    rebuilt after an edit copies the declarations the edit changed this way, their
    references into the others going to those kept. The members of collections
    ``left_out`` (by id) are not copied, nor what they hold: a product leaves out what
    it drops before anything reads it (:mod:`spl.resolver.resolution.pruning`)."""
    mapping: dict[int, EObject] = {}
    pending: list[tuple[EObject, EObject, tuple]] = []

    def clone(src: EObject) -> EObject:
        dst = src.eClass.python_class()
        mapping[id(src)] = dst
        values, references = _plan(src)
        if references:
            pending.append((src, dst, references))
        state = getattr(src, "__dict__", None)  # none: a plain element (spl.dsl.tsm.plain)
        for name, many, containment, default, feature in values:
            if many or state is None:
                value = getattr(src, name)
            else:  # read as pyecore's descriptor does, without the descriptor call
                slot = state.get(name)
                if slot is None:  # never set nor read: the default, not copied
                    continue
                value = slot._value if type(slot) is EValue else getattr(src, name)
            if many:
                if value:
                    items = list(value)
                    if containment:
                        items = [clone(c) for c in items if id(c) not in left_out]
                    if feature is not None:
                        _extend(dst, feature, name, items, containment)
                    else:
                        getattr(dst, name).extend(items)
            elif value is None or value == default:
                continue
            elif containment:
                if feature is not None:
                    _set_reference(dst, feature, name, clone(value), True)
                else:
                    setattr(dst, name, clone(value))
            elif feature is not None:
                _set_attribute(dst, feature, name, value)
            else:
                setattr(dst, name, value)
        return dst

    def mapped(value: EObject) -> EObject:
        found = mapping.get(id(value))
        if found is not None:
            return found
        return outside(value) if outside is not None else value

    copies = [clone(root) for root in roots]
    for src, dst, references in pending:
        for name, many, reference in references:
            value = getattr(src, name)
            if many:
                if value:
                    items = [mapped(v) for v in value]
                    if reference is not None:
                        _extend(dst, reference, name, items, False)
                    else:
                        getattr(dst, name).extend(items)
            elif value is None:
                continue
            elif reference is not None:
                _set_reference(dst, reference, name, mapped(value), False)
            else:
                setattr(dst, name, mapped(value))
    return copies, mapping


# The fields EValue(owner, attribute) sets besides owner, feature and _value, which are
# the same for every attribute (it is no reference, its type found on first check):
# filled in directly, since its __init__ (with a default value computed only to be
# replaced) was half of setting an attribute in a copy. tests/test_emf_copy.py checks
# the slots equal to pyecore's own.
_ATTRIBUTE_SLOT = {"is_ref": False, "is_cont": False, "generic_type": None}
_new_slot = object.__new__


def _set_attribute(obj: EObject, attribute: EAttribute, name: str, value: object) -> None:
    """``obj.name = value`` for a single-valued attribute of an object just created and
    not yet contained anywhere, as pyecore stores it: the value comes from the same
    attribute of the original (so it has the type), and nobody can listen to the new
    object yet, so pyecore's type check and notification (which walks up to the
    object's resource every time) have nothing to do; they were a third of a copy."""
    slot = _new_slot(EValue)
    slot.__dict__ = {"owner": obj, "feature": attribute, **_ATTRIBUTE_SLOT, "_value": value}
    obj.__dict__[name] = slot
    obj._isset[attribute] = None


def _direct(feature: EStructuralFeature) -> EStructuralFeature | None:
    """The feature when a copy sets it directly (:func:`_set_attribute`,
    :func:`_set_reference`, :func:`_extend`): an attribute or a reference without an
    opposite, not derived; None when pyecore's descriptor sets it."""
    if feature.derived or (not isinstance(feature, EAttribute) and feature.eOpposite):
        return None
    return feature


def _extend(
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


Step = tuple[str, int]  # a containment feature, and the position in it (-1: single-valued)


def fingerprint(
    root: EObject,
    target: Callable[[EObject], object],
    visit: Callable[[EObject, tuple[Step, ...]], None] | None = None,
    base: int = 0,
    leave_out: tuple[tuple[str, ...], ...] = (),
) -> tuple:
    """The content of the containment tree under ``root``, as nested tuples: the class
    and values of each element, source locations included, its children, and what
    ``target`` makes of each element it refers to (the caller's choice: the object's
    identity, a name, a path). Equal for two trees that hold the same values at the same
    places and refer to the same things, for memos keyed on a model's content (the
    editor's witness resolutions, the template's declarations); cheaper than building
    anything from the model, and exact where :func:`spl.core.emf_compare.differences` is
    lenient (locations).
    ``visit`` is told each element with its path of steps from ``root``. Reads plain
    elements (``spl.dsl.tsm.plain``) as it reads pyecore objects. Lines print less
    ``base`` (a declaration moved whole prints the same), and the containments whose
    trail of feature names from ``root`` is in ``leave_out`` are left out."""

    def walk(obj: EObject, path: tuple[Step, ...]) -> tuple:
        if visit is not None:
            visit(obj, path)
        values, references = _plan(obj)
        found: list[object] = [_NAMES[id(obj.eClass)]]
        for name, many, containment, _, _ in values:
            value = getattr(obj, name)
            if not containment:
                if name == "srcLine" and value is not None:
                    value -= base
                found.append(tuple(value) if many else value)
            elif leave_out and (*(f for f, _ in path), name) in leave_out:
                continue
            elif many:
                found.append(tuple(walk(c, (*path, (name, i))) for i, c in enumerate(value)))
            else:
                found.append(None if value is None else walk(value, (*path, (name, -1))))
        for name, many, _ in references:
            value = getattr(obj, name)
            if many:
                found.append(tuple(target(v) for v in value))
            else:
                found.append(None if value is None else target(value))
        return tuple(found)

    return walk(root, ())


def element_at(root: EObject, path: tuple[Step, ...]) -> EObject:
    """The element at ``path`` (steps of :func:`fingerprint`) below ``root``."""
    element = root
    for feature, position in path:
        value = getattr(element, feature)
        element = value if position < 0 else value[position]
    return element


def references(root: EObject) -> Iterator[tuple[EObject, EStructuralFeature, EObject]]:
    """Every reference of the tree under ``root`` that pyecore records on its target
    (no containment, no derived reference, none with an opposite): (the element
    referring, the reference, the element referred to)."""
    stack = [root]
    while stack:
        element = stack.pop()
        values, plain_references = _plan(element)
        for name, many, containment, _, _ in values:
            if containment:
                value = getattr(element, name)
                if many:
                    stack.extend(value)
                elif value is not None:
                    stack.append(value)
        for name, many, feature in plain_references:
            if feature is None:  # derived, or with an opposite
                continue
            value = getattr(element, name)
            for target in value if many else [value] if value is not None else []:
                yield element, feature, target


def forget_references(root: EObject) -> None:
    """Drop the records pyecore keeps, on each element the tree under ``root`` refers to,
    of those references. A model referring into a long-lived one (a resolution model
    into a template the editor keeps) would otherwise stay reachable from it after its
    last use, one more with every edit."""
    for element, feature, target in references(root):
        inverse = getattr(target, "_inverse_rels", None)
        if inverse is not None:
            inverse.discard((element, feature))


def adopt(owner: EObject, name: str, children: list[EObject]) -> None:
    """``children``, elements another model contained, appended to ``owner``'s
    containment ``name`` as a copy adds its own (:func:`_extend`). The model they leave
    must not be used again: its collection still lists them, but they are ``owner``'s,
    and they no longer keep it alive."""
    feature = owner.eClass.findEStructuralFeature(name)
    for child in children:
        before = child.eContainer()
        if before is not None:
            child._inverse_rels.discard((before, child._containment_feature))
    _extend(owner, feature, name, children, True)


def move_lines(root: EObject, delta: int, leave_out: tuple[tuple[str, ...], ...] = ()) -> None:
    """Every source line in the tree under ``root`` moved by ``delta`` (but in the
    containments left out as :func:`fingerprint` leaves them out), in place: the editor
    takes over a declaration whose text only moved (:mod:`spl.dsl.tsm.declarations`). A
    line never set stays unset. Set in pyecore's slot, without notification: nobody
    listens to the editor's template."""
    stack: list[tuple[EObject, tuple[str, ...]]] = [(root, ())]
    while stack:
        element, trail = stack.pop()
        slot = element.__dict__.get("srcLine")
        if type(slot) is EValue and slot._value:
            slot._value += delta
        eclass = element.eClass
        children = _CHILDREN.get(id(eclass))
        if children is None:
            values, _ = _plan(element)
            children = _CHILDREN[id(eclass)] = tuple((n, m) for n, m, c, _, _ in values if c)
        for name, many in children:
            if leave_out and (*trail, name) in leave_out:
                continue
            value = getattr(element, name)
            below = (*trail, name) if leave_out else ()
            if many:
                stack.extend((child, below) for child in value)
            elif value is not None:
                stack.append((value, below))


_CHILDREN: dict[int, tuple[tuple[str, bool], ...]] = {}  # each class's containments


def replace_members(owner: EObject, name: str, members: list[EObject]) -> None:
    """``owner``'s containment ``name`` made ``members``, in order, elements of this or
    another model (:func:`adopt`); those it held before and does not hold now must not be
    used again."""
    collection = getattr(owner, name)
    if list(collection) == members:
        return
    kind = type(collection)
    if kind is EOrderedSet or kind is ESet:
        OrderedSet.clear(collection)
    elif kind is EList or kind is EBag:
        list.clear(collection)
    else:
        collection.clear()
    adopt(owner, name, members)
