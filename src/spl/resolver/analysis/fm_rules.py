"""The rules of a feature model, as explanations name them.

Every clause of the CNF (:mod:`spl.resolver.analysis.cnf`) belongs to exactly one :class:`Rule` —
the root, a child-needs-parent edge, a mandatory child, a group, or a cross-tree
constraint — and the rule keeps its model element and source location, so an
unsatisfiable selection (:mod:`spl.resolver.resolution.selection`) can be explained by naming the
rules it violates, in the words the author wrote them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple, cast

from spl.core.diagnostics import Location, location_of
from spl.dsl.fm.printer import format_formula

if TYPE_CHECKING:
    from spl.dsl.fm.plain import FmConstraint, FmFeature, FmGroup


class Rule(NamedTuple):
    """One model element's contribution to the formula; explanations quote ``text``.

    ``features`` are the features the rule talks about: for tree rules (child, parent),
    for a group (parent, *members); for a constraint its features in first-use order.
    The wording and the location are built only when asked for, and the rule is a named
    tuple: encoding a 2500-feature model must not pay for thousands of sentences nobody
    reads.
    """

    index: int  # type: ignore[assignment]  # the rule's number (shadows tuple.index)
    kind: str  # root | parent | mandatory | group | constraint
    element: FmFeature | FmGroup | FmConstraint  # a group's for a group, ...
    features: tuple[str, ...] = ()
    bounds: tuple[int, int] = (0, -1)  # a group's (lower, upper as written, -1 = *)
    formula: tuple | None = None  # constraints: the formula as a tree of tuples

    @property
    def location(self) -> Location | None:
        """Where the rule is written (looked up on demand: most rules are never reported)."""
        where = location_of(self.element)
        if where is None and self.kind == "constraint":
            where = location_of(cast("FmConstraint", self.element).formula)
        return where

    @property
    def text(self) -> str:
        kind, names = self.kind, self.features
        if kind == "root":
            return f"{names[0]} is the root feature and always selected"
        if kind == "parent":
            return f"{names[0]} needs its parent {names[1]}"
        if kind == "mandatory":
            return f"{names[0]} is mandatory in {names[1]}"
        if kind == "constraint":
            return format_formula(cast("FmConstraint", self.element).formula)
        group = cast("FmGroup", self.element)
        parent, listed = names[0], ", ".join(names[1:])
        lower, upper = self.bounds
        if group_kind(group) == "alternative":
            return f"{parent}: exactly one of {listed}"
        if group_kind(group) == "or":
            return f"{parent}: at least one of {listed}"
        if upper < 0:
            return f"{parent}: at least {lower} of {listed}"
        return f"{parent}: between {lower} and {upper} of {listed}"

    def __str__(self) -> str:
        return f"{self.text} ({self.location})" if self.location else self.text


def group_kind(group: FmGroup) -> str:
    kind = group.kind
    return kind.name if hasattr(kind, "name") else str(kind)


def group_bounds(group: FmGroup, kind: str | None = None, n: int | None = None) -> tuple[int, int]:
    """(lower, upper) of a group, upper ``-1`` meaning unbounded."""
    n = len(group.features) if n is None else n
    kind = group_kind(group) if kind is None else kind
    if kind == "mandatory":
        return n, n
    if kind == "optional":
        return 0, n
    if kind == "alternative":
        return 1, 1
    if kind == "or":
        return 1, n
    return int(group.lower or 0), int(group.upper if group.upper is not None else -1)
