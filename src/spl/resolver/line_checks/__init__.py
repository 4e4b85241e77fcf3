"""Checks of a product line as a whole (docs/commands.md, "spl check"), before any product
is derived.

The engine finds a conflict only in the one product it resolves; a CI job wants to
know that *no* product of the line can hit one, without deriving them all. Each check
here asks the SAT solver about the activation literals of resolution elements
(``F`` for ``when F selected``, ``-F`` for ``when F not selected``) under assumptions,
so the cost grows with the number of elements and of candidate pairs, never with the
number of products:

========  ========  ==================================================================
code      severity  finding
========  ========  ==================================================================
SPL010    error     a resolution element that can never be active (its feature is dead,
                    or core for ``not selected``), with the feature-model rules why
SPL011    warning   an optional node or store no product can contain: no element that
                    can be active requires or transforms it
SPL012    error     two transformations of elements that can be active in one product
                    decide one thing differently (implementation, parameter value,
                    refinement period, migration target, topic, server, sharing mode);
                    the message names a witness product
SPL013    error     a migration to a missing container or to the node's own container
                    (found by the .rm parser, ``spl.dsl.rm.language.MIGRATION_TARGET``, so
                    ``spl check DIR`` reports it on parsing)
SPL014    info      a concrete leaf feature with no effect: no resolution element,
                    attribute, sharing mode or constraint mentions it
SPL015    warning   a listed product (``products/*.yaml``) that is not a valid, complete
                    selection
SPL016    error     a statement that fails in some product activating its element: a
                    topic missing where the node is at that point, a client and server
                    apart, ... (:mod:`.lookups`, docs/semantics.md C3);
                    the message names a witness product
SPL017    warning   two robot containers with one robot_id (or ids differing only in
                    case): products keeping both fail unless their deployment sets one
SPL018    error     a robot container whose endpoint has no user or password env (no
          warning   product keeping it resolves), or no robot_id or url (each such
                    product must set it in its deployment)
SPL019    warning   two instances of the template (robots, cloud partitions) that would
                    get one Rapyuta tag, or tags differing only in case
SPL050    warning   a flow the template draws from one robot through a private cloud
                    node to another robot, which the per-robot instances never deliver
                    (:mod:`.cross_robot`); the message names a witness product
SPL045    warning   a subscriber some product keeps with nothing feeding it, and
SPL046              a service client some product keeps with no server answering it
                    (:mod:`.dataflow`); the message names a witness product and what
                    removes the feeders, as ``spl resolve`` of that product warns
SPL052    info      a publisher whose data no subscriber of any product reads
                    (:mod:`.unconsumed`)
========  ========  ==================================================================

One module a check family; this package runs them all. :class:`ActivationSolver`
(:mod:`.activation`) answers the SAT questions of every check but SPL014 and SPL015: one
solver those that read only the .rm and .fm (:mod:`.statements`), one the dataflow
checks (:mod:`.dataflow_memory`: the editor keeps their findings), another the rest.
"""

from __future__ import annotations

from spl.core.cyclic_gc import without_cyclic_gc
from spl.core.diagnostics import Diagnostic, Location
from spl.dsl.workspace import Workspace
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.line_checks.cross_robot import cross_robot_flows_in_line
from spl.resolver.line_checks.dataflow_memory import dataflow_findings_kept
from spl.resolver.line_checks.endpoints import incomplete_endpoints
from spl.resolver.line_checks.instance_tags import clashing_instance_tags
from spl.resolver.line_checks.listed_products import read_listed, unresolvable_products
from spl.resolver.line_checks.robot_ids import shared_robot_ids
from spl.resolver.line_checks.statements import statement_findings
from spl.resolver.line_checks.unreachable_optionals import unreachable_optional_elements
from spl.resolver.resolution.product_line import ProductLine


def check_product_line(
    line: ProductLine, products: bool = True, workspace: Workspace | None = None
) -> list[Diagnostic]:
    """Every line check, sorted by location; ``products`` includes the listed products.
    In the editor's ``workspace`` (the line loaded through it), its unsaved texts stand
    in for the listed products' files, and what its memory of the line keeps that is
    still right is not found again (:mod:`.witnesses`, :mod:`.statements`)."""
    # what the checks build (witness products, their resolutions, clauses) is dropped
    # with them: a 10,000-node line's checks took twice as long with the collector on
    with without_cyclic_gc("dropped"):
        found = _line_checks(line, products, workspace)
    return sorted(found, key=diagnostic_order)


def _line_checks(
    line: ProductLine, products: bool, workspace: Workspace | None
) -> list[Diagnostic]:
    listed = read_listed(line, workspace.texts if workspace is not None else None)
    found = statement_findings(line, workspace)  # the .rm's own, on a solver of their own
    with ActivationSolver(line) as solver:
        solver.decide(list(line.rm.elements))  # each element's activity, in few models
        found += unreachable_optional_elements(line, solver)
        found += cross_robot_flows_in_line(line, solver, listed, workspace)
    found += dataflow_findings_kept(line, workspace)  # on a solver of their own
    found += shared_robot_ids(line)
    found += incomplete_endpoints(line)
    found += clashing_instance_tags(line, listed)
    if products:
        found += unresolvable_products(line, listed)
    return found


def diagnostic_order(d: Diagnostic) -> tuple:
    loc = d.location or Location("")
    return (loc.file, loc.line, loc.col, d.code or "", d.message)
