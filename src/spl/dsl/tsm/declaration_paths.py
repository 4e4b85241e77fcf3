"""Where an element of a template is: the declaration it is in (:mod:`.declarations`) and
the steps down to it, a path that compares across readings of a .tsm where the element
itself does not (each reading makes new objects).

Read off pyecore objects through their containment features, and off plain ones
(:mod:`spl.dsl.tsm.plain`, which keep only their container) by looking for the element
in its container's containments.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from spl.core.emf import Step
from spl.core.emf_copy import plan

# a container's members, declarations of their own: its topics, nodes and stores, and its
# endpoint's interfaces (placed where the bridges that make them are, not in the container)
MEMBERS = ("topics", "nodes", "stores", "interfaces")
# (feature, name), or (feature, position) for an unnamed bridge; a container's member:
# the container's key, then (feature, name)
Key = tuple
Path = tuple[Key, tuple[Step, ...]]  # the declaration, then the steps down to the element
Index = Callable[[Any, Any], "int | None"]  # where an element is in a list, None if not


def _scan(members: Any, element: Any) -> int | None:
    """Where ``element`` is in ``members``, looked for one by one."""
    return next((i for i, member in enumerate(members) if member is element), None)


def declaration_of(element: Any, index: Index = _scan) -> Any:
    """The declaration ``element`` is in (itself, for a declaration): a top-level one,
    or a container's member (a topic, node, store or endpoint interface)."""
    while (owner := element.eContainer()) is not None and owner.eContainer() is not None:
        if _is_member(element, index):
            return element
        element = owner
    return element


def _containment(element: Any, index: Index = _scan) -> tuple[str, bool] | None:
    """The name of the feature holding ``element`` in its container, and whether it is
    many-valued (a plain element, :mod:`spl.dsl.tsm.plain`, is looked for there, through
    ``index``)."""
    feature_of = getattr(element, "eContainmentFeature", None)
    if feature_of is not None:
        feature = feature_of()
        return None if feature is None else (feature.name, feature.many)
    owner = element.eContainer()
    if owner is None:
        return None
    for name, many, containment, _, _ in plan(owner)[0]:
        if not containment:
            continue
        value = getattr(owner, name)
        if many and index(value, element) is not None:
            return name, True
        if not many and value is element:
            return name, False
    return None


def _is_member(element: Any, index: Index = _scan) -> bool:
    feature = _containment(element, index)
    if feature is None or feature[0] not in MEMBERS:
        return False
    return feature[0] != "interfaces" or element.eContainer().eClass.name == "Endpoint"


def path_of(element: Any, index: Index = _scan) -> Path:
    """The path (:class:`Declarations`) of an element of a template (``index``: where an
    element is in a list of members, when the caller keeps that)."""
    steps: list[Step] = []
    declaration = declaration_of(element, index)
    while element is not declaration:
        owner = element.eContainer()
        name, many = _containment(element, index)  # type: ignore[misc]  # it is contained
        members = getattr(owner, name)
        at = index(members, element) if many else -1
        assert at is not None  # contained: it is there
        steps.append((name, at))
        element = owner
    return _key_of(declaration), tuple(reversed(steps))


def _key_of(declaration: Any) -> Key:
    owner = declaration.eContainer()
    feature = _containment(declaration)[0]  # type: ignore[index]  # contained: it has one
    if owner.eContainer() is None:
        members = getattr(owner, feature)
        return (feature, getattr(declaration, "name", None) or members.index(declaration))
    container = owner if feature != "interfaces" else owner.eContainer()  # an endpoint's
    return (*_key_of(container), feature, declaration.name)


def target_paths(system: Any, paths: dict[int, Path]) -> Callable[[Any], Path]:
    """The path of a target referred to: as read, or, for an element of a declaration
    not read, worked out from its place in ``system``; a target outside the model
    (none is) never prints as anything seen before."""
    positions: dict[int, dict[int, int]] = {}  # id of a list -> id of a member -> index

    def index(members: Any, element: Any) -> int | None:
        found = positions.get(id(members))
        if found is None:
            found = positions[id(members)] = {id(m): i for i, m in enumerate(members)}
        return found.get(id(element))

    def path(target: Any) -> Path:
        known = paths.get(id(target))
        if known is not None:
            return known
        top = target
        while top.eContainer() is not None:
            top = top.eContainer()
        if top is not system:
            return ("outside", id(target)), ()
        return path_of(target, index)

    return path
