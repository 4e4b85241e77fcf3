"""SPL010: resolution elements no product activates, dead code in the resolution model.

An element ``when F selected`` can never be active when ``F`` is dead, ``when F not
selected`` when ``F`` is core; the message quotes the feature-model rules that make it so
(the minimal explanation of :func:`spl.resolver.resolution.selection.check_selection`).
"""

from __future__ import annotations

from spl.core.diagnostics import Diagnostic, location_of
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.selection import check_selection

DEAD_ELEMENT = "SPL010"


def never_active_elements(line: ProductLine, solver: ActivationSolver) -> list[Diagnostic]:
    """Elements no product activates: dead code in the resolution model."""
    solver.decide(list(line.rm.elements))
    found = []
    for element in line.rm.elements:
        if solver.possible(element):
            continue
        name = element.feature.name
        if element.activeIfSelected:
            check = check_selection(line.formula, [name])
            state, why = "selected", f"feature {name} is dead (in no product)"
        else:
            check = check_selection(line.formula, [], [name])
            state, why = "not selected", f"feature {name} is core (in every product)"
        reason = check.explanation()
        found.append(
            Diagnostic(
                location_of(element),
                f"resolution element 'when {name} {state}' can never be active: {why}"
                + (f", because {reason}" if reason else ""),
                "error",
                DEAD_ELEMENT,
            )
        )
    return found
