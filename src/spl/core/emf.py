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
from pyecore.ecore import EObject, EStructuralFeature
from pyecore.valuecontainer import EBag, EList, EOrderedSet, ESet, EValue

from spl.core.emf_copy import TreeImage, class_name, extend, plan


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
    it drops before anything reads it (:mod:`spl.resolver.resolution.pruning`). A tree
    copied more than once is read once as a :class:`spl.core.emf_copy.TreeImage`."""
    return TreeImage(roots).copy(outside, left_out)


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
        values, references = plan(obj)
        found: list[object] = [class_name(obj)]
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
        values, plain_references = plan(element)
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
    containment ``name`` as a copy adds its own (:func:`spl.core.emf_copy.extend`). The
    model they leave must not be used again: its collection still lists them, but they
    are ``owner``'s, and they no longer keep it alive."""
    feature = owner.eClass.findEStructuralFeature(name)
    for child in children:
        before = child.eContainer()
        if before is not None:
            child._inverse_rels.discard((before, child._containment_feature))
    extend(owner, feature, name, children, True)


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
            values, _ = plan(element)
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
