"""The line checks that read only the resolution model, the feature model and the template
elements the .rm names: elements no product activates (SPL010), conflicts (SPL012),
features without effect (SPL014) and statements that fail in some product (SPL016).

They run on a solver of their own, so what they ask leaves the witnesses the other
checks find as they are. The editor keeps their findings while its .rm and .fm models
are the very ones they were found on (its workspace's memory of the line,
:class:`spl.dsl.workspace.LineMemory`): the editor keeps a
.rm model only while it means the same against the template
(:mod:`spl.dsl.rm.reuse`: every declaration it refers into taken over, no declaration
the edit changed declaring a word of its text), and a .fm text is built once, so an
edit of the .tsm that leaves them cannot change these findings. On a 10,000-node line
they are a tenth of a second of every check.
"""

from __future__ import annotations

import weakref

from spl.core.diagnostics import Diagnostic
from spl.dsl.workspace import Workspace
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.line_checks.conflicts import reachable_conflicts
from spl.resolver.line_checks.dead_elements import never_active_elements
from spl.resolver.line_checks.lookups import product_dependent_statements
from spl.resolver.line_checks.no_effect import features_without_effect
from spl.resolver.resolution.product_line import ProductLine


class StatementFindings:
    """The findings of these checks on one line, kept with the models they read."""

    def __init__(self) -> None:
        self._kept: tuple[weakref.ref, weakref.ref, list[Diagnostic]] | None = None

    def findings(self, line: ProductLine) -> list[Diagnostic]:
        kept = self._kept
        if kept is not None and kept[0]() is line.rm and kept[1]() is line.fm:
            return list(kept[2])
        found = _checked(line)
        self._kept = (weakref.ref(line.rm), weakref.ref(line.fm), found)
        return list(found)


def statement_findings(line: ProductLine, workspace: Workspace | None = None) -> list[Diagnostic]:
    """SPL010, SPL012, SPL014 and SPL016 on ``line``; in an editor's ``workspace`` that
    remembers the line, found again only on other models."""
    memory = workspace.line_memory(line.directory) if workspace is not None else None
    return memory.of(StatementFindings).findings(line) if memory is not None else _checked(line)


def _checked(line: ProductLine) -> list[Diagnostic]:
    with ActivationSolver(line) as solver:
        found = never_active_elements(line, solver)
        found += reachable_conflicts(line, solver)
        found += product_dependent_statements(line, solver)
    return found + features_without_effect(line)
