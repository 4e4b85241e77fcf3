"""The dataflow checks' findings (SPL045, SPL046 and SPL052), kept in the editor's memory
of a line from one check to the next while nothing the checks read changed
(docs/editors.md, "What the editor keeps").

Why: on a 10,000-node line they were half of every check the editor runs after a valid
edit (the template's flows, the feeds of every input and every output, a thousand SAT
questions), while the edits made most often while a line grows, a node typed in before
any resolution element requires it, change nothing they read.

The checks (:mod:`.dataflow`, :mod:`.unconsumed`) run on a solver of their own, so
their findings are a function of what they read: the template's declarations, the
feature model and the resolution elements (with their places: messages cite them), and
the witness products' resolutions, which read no more than that (:mod:`.witnesses`).
Left out of the comparison is an optional node no resolution element names, no other
declaration refers into and with no publisher or server, and a container of only those:
no product keeps such a node, so the checks ask nothing about its inputs, it feeds no
input and reads no output in any product, and every witness resolution drops it before
reading the architecture. When the declarations read only moved, the findings move with
the declaration each is in (:func:`.witnesses.moved_findings`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from spl.core.diagnostics import Diagnostic
from spl.core.emf import references
from spl.dsl.tsm.declaration_paths import declaration_of
from spl.metamodels import interface_kinds, tsm
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.line_checks.dataflow import unfed_inputs_in_line
from spl.resolver.line_checks.unconsumed import unconsumed_outputs_in_line
from spl.resolver.line_checks.witnesses import (
    Lines,
    line_in_editor,
    moved_findings,
    referred_declarations,
    template_reads,
)
from spl.resolver.resolution.product_line import ProductLine

if TYPE_CHECKING:
    from spl.dsl.tsm.declaration_paths import Key
    from spl.dsl.tsm.declarations import BuiltTemplate
    from spl.dsl.workspace import Workspace


class DataflowFindings:
    """The dataflow checks' last findings on one line, with what they were made on; what
    they read of it is worked out when first compared (an edit of the .rm, which makes
    another .rm model, has the checks run again without it)."""

    def __init__(self) -> None:
        self._findings: tuple[Diagnostic, ...] = ()
        # the .rm model they were made with, and the declarations it names: an edit of
        # the .tsm alone leaves the model as it was (spl.dsl.rm.reuse), with its elements
        # and their places; another model is taken as another content
        self._rm: object = None
        self._named: set[Key] | None = None
        self._fm: object = None
        self._built: BuiltTemplate | None = None  # the template they were made on
        self._reads: tuple[tuple, Lines] | None = None  # what they read of it
        self.checks = 0  # how often the checks ran (the rest were kept)

    def findings(
        self, line: ProductLine, built: BuiltTemplate, workspace: Workspace | None
    ) -> list[Diagnostic]:
        """The checks' findings on ``line`` (its template as the editor ``built`` it),
        found again only when what they read changed."""
        if line.rm is not self._rm:
            self._rm, self._named, self._built = line.rm, None, None
        reads = None
        if self._built is not None:
            if self._named is None:
                self._named = _named(line, built)
            if self._reads is None:
                self._reads = _dataflow_reads(self._fm, self._built, self._named)
            reads = _dataflow_reads(line.fm, built, self._named)
            if reads[0] == self._reads[0]:
                before, kept = self._reads[1], self._findings
                moved = moved_findings(before, kept, reads[1], line.tsm.srcFile)
                if moved is not None:
                    return self._made(line, built, reads, moved)
        self.checks += 1
        return self._made(line, built, reads, tuple(dataflow_findings(line, workspace)))

    def _made(
        self,
        line: ProductLine,
        built: BuiltTemplate,
        reads: tuple[tuple, Lines] | None,
        findings: tuple[Diagnostic, ...],
    ) -> list[Diagnostic]:
        """``findings``, kept as made on ``built`` (``reads``: what they read of it, if
        worked out)."""
        self._fm, self._built, self._reads, self._findings = line.fm, built, reads, findings
        return list(findings)


def dataflow_findings(line: ProductLine, workspace: Workspace | None = None) -> list[Diagnostic]:
    """The unfed inputs and the unconsumed outputs of the line, on a solver of their own:
    the same answers and witnesses whatever the other checks asked before (what lets
    the editor keep them)."""
    with ActivationSolver(line) as solver:
        return unfed_inputs_in_line(line, solver, workspace) + unconsumed_outputs_in_line(
            line, solver
        )


def dataflow_findings_kept(line: ProductLine, workspace: Workspace | None) -> list[Diagnostic]:
    """The dataflow checks, their findings kept in the editor's ``workspace`` when it
    keeps the line and its template's declarations (:class:`DataflowFindings`)."""
    memory, built = line_in_editor(line, workspace) or (None, None)
    if memory is None or built is None:
        return dataflow_findings(line, workspace)
    return memory.of(DataflowFindings).findings(line, built, workspace)


def _named(line: ProductLine, built: BuiltTemplate) -> set[Key]:
    """The template's declarations the line's resolution elements refer into."""
    keys = {id(element): key for key, element in built.elements.items()}
    package = tsm().package
    named = {
        keys.get(id(declaration_of(target)))
        for element in line.rm.elements
        for _, _, target in references(element)
        if target.eClass.ePackage is package
    }
    return {key for key in named if key is not None}


def _dataflow_reads(fm: Any, built: BuiltTemplate, named: set[Key]) -> tuple[tuple, Lines]:
    """What the dataflow checks read of the template ``built`` and the feature model
    ``fm``, comparable, and the lines of the declarations read: every declaration but
    the nodes in no product that could feed nothing, and the containers of only those
    (``named``: the declarations the resolution elements refer into)."""
    found = built.declarations
    referred, referred_containers = referred_declarations(found)

    def feeds_nothing(key: Key) -> bool:
        declaration = found.items[key]
        if len(key) != 4 or key[2] != "nodes" or not declaration.droppable:
            return False
        if key in referred or key in named:
            return False
        node = built.elements[key]
        return not any(interface_kinds.kind_of(i).provides for i in node.interfaces)

    left_out = {key for key in found.items if feeds_nothing(key)}
    members: dict[Key, list[Key]] = {}
    for key in found.items:
        if len(key) == 4:
            members.setdefault(key[:2], []).append(key)
    left_out |= {
        container
        for container, inside in members.items()
        if container not in referred_containers
        and container not in named
        and all(k in left_out for k in inside)
    }
    read = [k for k in found.items if k not in left_out]
    return template_reads(fm, found, read, ())
