"""The kinds of resolution statements (the four transformation kinds of the mapping paper,
*A Software Product Line Approach for Configuring Cloud Robotics Applications*, as
docs/index.md names it; the connection kind split by what it connects), one class per
module, and their registry.

Everything that acts on or reasons about a ``.rm`` statement asks its kind
(:func:`kind_of`): the engine applies it, the product-line checks ask what it keeps,
decides and may fail at, the fleet analysis what it does to nodes. Adding a kind is a
new module with a :class:`~.kind.TransformationKind` subclass and its line in
``KINDS`` (docs/architecture.md).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from spl.resolver.resolution.transformations.bridge import ConnectBridge
from spl.resolver.resolution.transformations.implementation import Implementation
from spl.resolver.resolution.transformations.kind import TransformationKind
from spl.resolver.resolution.transformations.migration import NodeMigration
from spl.resolver.resolution.transformations.new_topic import ConnectToNewTopic
from spl.resolver.resolution.transformations.parameter import ParameterValue
from spl.resolver.resolution.transformations.to_server import ConnectService
from spl.resolver.resolution.transformations.to_topic import ConnectToTopic

if TYPE_CHECKING:
    from spl.metamodels import rm_types, tsm_types

# by the rm.ecore class a kind is of (a statement reaches its kind by its class's name,
# so the kinds' statement types are one for the table)
KINDS: dict[str, TransformationKind[Any]] = {
    kind.metaclass: kind
    for kind in (
        Implementation(),
        ConnectToTopic(),
        ConnectToNewTopic(),
        ConnectService(),
        ConnectBridge(),
        ParameterValue(),
        NodeMigration(),
    )
}


def kind_of(transformation: rm_types.Transformation) -> TransformationKind[Any]:
    """The kind of a ``.rm`` statement (by its rm.ecore class, looked up by its Python
    class: the line checks ask this some 40,000 times of a 500-element line)."""
    kind = _BY_TYPE.get(type(transformation))
    if kind is None:
        kind = _BY_TYPE[type(transformation)] = KINDS[transformation.eClass.name]
    return kind


_BY_TYPE: dict[type, TransformationKind[Any]] = {}


def touched_elements(
    element: rm_types.ResolutionElement,
) -> Iterator[tsm_types.NamedElement]:
    """The nodes and stores a resolution element keeps in a product when it is active
    (what the engine's ``keep`` is called with): its required ones, and those its
    statements keep."""
    yield from element.required
    for t in element.transformations:
        yield from kind_of(t).touched(t)


def sharing_targets(element: rm_types.ResolutionElement) -> list[tsm_types.NamedElement]:
    """The template elements a resolution element's feature gives its sharing mode to: the
    ones it requires and the nodes it implements or migrates (stores among them too; the
    callers keep what they need)."""
    return list(element.required) + [
        node for t in element.transformations for node in kind_of(t).shares(t)
    ]


def moves(element: rm_types.ResolutionElement) -> list[tuple[tsm_types.Node, tsm_types.Container]]:
    """(node, target container) of the element's migrations, in order."""
    return [m for t in element.transformations if (m := kind_of(t).move(t)) is not None]
