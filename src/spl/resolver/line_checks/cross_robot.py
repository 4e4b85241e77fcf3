"""SPL050 before any product is chosen: a flow the template draws from one robot, through
a private cloud node, to another robot, which the per-robot instances never deliver.

A private node runs once per robot, and each instance exchanges data with its own robot
only (docs/semantics.md F4). So when the data of robot A reaches a private node and the
node feeds robot B, B gets the output of its own instance, which A's data never reaches.
``spl resolve`` warns in each product where that happens; this check finds the products
from the template: the flows of the .tsm as written (:class:`FlowTable` of the
template), the nodes that can be private (private in the .tsm and given no other mode by
a feature, or given ``private`` by a feature's sharing default), and one SAT question
per candidate: a product keeping the node, the robot side at both ends, and none of
B's nodes that would feed the node itself. The witness is resolved, and the warning is
reported as that product's resolution gives it, naming the product; a candidate whose
witness resolves without it (a migration or a connection changed the flows) is not
reported. A listed product (``products/*.yaml``) that makes a feature's nodes private
with its ``sharing:`` choice is resolved too, and its warnings are reported naming it.
Flows that only a resolution element's ``connect`` or migration draws in an unlisted
product are found by ``spl resolve`` in the product that has them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from spl.core.diagnostics import Diagnostic, ModelError, location_of
from spl.resolver.architecture.flows import node_of
from spl.resolver.architecture.placement import sharing_mode
from spl.resolver.architecture.wiring import CROSS_ROBOT, cut_off
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.line_checks.listed_products import Listed
from spl.resolver.line_checks.presence import Presence
from spl.resolver.line_checks.witnesses import witness_warnings
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.product_selection import ProductSelection
from spl.resolver.resolution.transformations import sharing_targets

if TYPE_CHECKING:
    from spl.dsl.workspace import Workspace
    from spl.metamodels import tsm_types


def cross_robot_flows_in_line(
    line: ProductLine, solver: ActivationSolver, listed: Listed, workspace: Workspace | None = None
) -> list[Diagnostic]:
    robots = [c for c in line.tsm.containers if c.eClass.name == "RobotContainer"]
    if len(robots) < 2:
        return []
    found = [
        Diagnostic(w.location, f"{w.message}, in the listed product {path.stem}", w.severity,
                   w.code)
        for path, selection in listed
        if not isinstance(selection, ModelError) and "private" in selection.sharing.values()
        for w in _warnings(line, selection)
    ]  # fmt: skip
    presence = Presence(line, solver)
    mode_by: dict[int, list[tuple[int, str]]] = {}  # node -> (literal, mode) of sharing elements
    for element in line.rm.elements:
        if element.feature.sharing is not None:
            for node in sharing_targets(element):
                mode = element.feature.sharing.mode.name
                mode_by.setdefault(id(node), []).append((solver.literal(element), mode))

    def can_be_private(node: tsm_types.Node) -> bool:
        modes = {mode for _, mode in mode_by.get(id(node), ())}
        return "private" in modes or sharing_mode(node) == "private"

    def private(node: tsm_types.Node) -> list[list[int]]:
        others = [[-lit] for lit, mode in mode_by.get(id(node), ()) if mode != "private"]
        if sharing_mode(node) == "private":
            return others
        return [*others, [lit for lit, mode in mode_by.get(id(node), ()) if mode == "private"]]

    template = line.template_flows
    for cut in cut_off(template, can_be_private):
        node = node_of(cut.giver)
        feeder = cut.feeders[0][1].source if cut.feeders[0][1].kind.on_topic else None
        ends = [node, node_of(cut.taker)] + ([node_of(feeder)] if feeder else [])
        clauses: list[list[int]] | None = private(node)
        for end in ends:
            keep = presence.present(end)
            clauses = None if keep is None or clauses is None else clauses + keep
        for flow in template.flows:  # none of the taker's robot may feed the node itself
            giver, taker = flow.provider, flow.consumer
            mine = taker.eContainer() is node and giver.eContainer().eContainer() is cut.robot
            if clauses is not None and mine:
                drop = presence.absent(node_of(giver))
                clauses = None if drop is None else clauses + drop
        if clauses is None:
            continue
        witness = solver.witness_where(None, clauses)
        if witness is not None:
            found += _confirmed(line, witness, cut.taker, workspace)
    return found


def _warnings(line: ProductLine, selection: ProductSelection) -> list[Diagnostic]:
    """The SPL050 warnings of one listed product (none when it fails for other reasons,
    which resolve and validate report)."""
    from spl.resolver.resolution.engine import (
        resolve,  # the engine checks products; checks import it late
    )

    try:
        product = resolve(line, selection).product
    except ModelError:
        return []
    return [w for w in product.warnings if w.code == CROSS_ROBOT]


def _confirmed(
    line: ProductLine,
    witness: tuple[str, ...],
    taker: tsm_types.Interface,
    workspace: Workspace | None,
) -> list[Diagnostic]:
    """The witness product's own SPL050 at ``taker``, naming the product."""
    where = location_of(taker)
    named = f", in the product {', '.join(witness)}"
    return [
        Diagnostic(w.location, w.message + named, w.severity, w.code)
        for w in witness_warnings(line, witness, workspace)
        if w.code == CROSS_ROBOT and w.location == where
    ]
