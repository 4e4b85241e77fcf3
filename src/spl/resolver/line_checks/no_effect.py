"""SPL014: concrete leaf features nothing reads.

Choosing such a feature changes no product's architecture, attributes or sharing, and
it constrains no other feature: no resolution element, attribute, sharing mode or
constraint mentions it (a leaf of an alternative group whose sibling has a ``not
selected`` element does matter: choosing it deselects that sibling).
"""

from __future__ import annotations

from spl.core.diagnostics import Diagnostic, location_of
from spl.dsl.fm.language import all_features
from spl.resolver.analysis.formula_trees import formula_features, formula_tree
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.transformations import kind_of

NO_EFFECT = "SPL014"


def features_without_effect(line: ProductLine) -> list[Diagnostic]:
    """Concrete leaves that nothing reads: choosing them changes no product's architecture,
    attributes or sharing, and they constrain no other feature."""
    mentioned: set[str] = set()
    not_selected: set[str] = set()
    for element in line.rm.elements:
        mentioned.add(element.feature.name)
        if not element.activeIfSelected:
            not_selected.add(element.feature.name)
        for t in element.transformations:
            attribute = kind_of(t).attribute(t)
            if attribute is not None:
                mentioned.add(attribute.eContainer().name)
    for constraint in line.fm.constraints:
        mentioned.update(formula_features(formula_tree(constraint.formula)))
    found = []
    for feature in all_features(line.fm):
        if (
            feature.name in mentioned
            or feature.abstract
            or feature.groups
            or feature.attributes
            or feature.sharing is not None
        ):
            continue
        group = feature.eContainer()
        # in an alternative group, choosing this feature deselects its siblings: when a
        # sibling has a `not selected` element, the choice matters
        if group is not None and group.eClass.name == "Group":
            siblings = {f.name for f in group.features if f is not feature}
            if group.kind.name == "alternative" and siblings & not_selected:
                continue
        found.append(
            Diagnostic(
                location_of(feature),
                f"feature {feature.name} has no effect: no resolution element, attribute, "
                "sharing mode or constraint mentions it",
                "info",
                NO_EFFECT,
            )
        )
    return found
