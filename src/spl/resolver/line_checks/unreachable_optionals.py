"""SPL011: optional nodes and stores no product can contain.

An optional node or store enters a product only through an active resolution element
that requires or transforms it (:func:`spl.resolver.resolution.transformations.touched_elements`,
what
the engine keeps); when
no element that can be active touches it, it is in no product.
"""

from __future__ import annotations

from spl.core.diagnostics import Diagnostic, location_of
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.transformations import touched_elements

UNREACHABLE_OPTIONAL = "SPL011"


def unreachable_optional_elements(line: ProductLine, solver: ActivationSolver) -> list[Diagnostic]:
    """Optional nodes and stores that only enter a product through an active element."""
    reachable: set[int] = set()
    mentioned: set[int] = set()
    for element in line.rm.elements:
        touched = [id(x) for x in touched_elements(element)]
        mentioned.update(touched)
        if solver.possible(element):
            reachable.update(touched)
    found = []
    for container in line.tsm.containers:
        for what, members in (("node", container.nodes), ("store", container.stores)):
            for member in members:
                if not member.optional or id(member) in reachable:
                    continue
                why = (
                    "only resolution elements that can never be active require or transform it"
                    if id(member) in mentioned
                    else "no resolution element requires or transforms it"
                )
                found.append(
                    Diagnostic(
                        location_of(member),
                        f"optional {what} {container.name}.{member.name} is in no product: {why}",
                        "warning",
                        UNREACHABLE_OPTIONAL,
                    )
                )
    return found
