"""Which resolution elements can be active together: SAT questions about a product line.

The product-line checks (:mod:`spl.resolver.line_checks`, one module a check family) ask
them about the activation literals of resolution elements (``F`` for ``when F
selected``, ``-F`` for ``when F not selected``) under assumptions, so their cost grows
with the number of elements and questions, never with the number of products.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pysat.solvers import Solver

from spl.resolver.resolution.product_line import ProductLine

if TYPE_CHECKING:
    from spl.metamodels import rm_types

# how many models found are kept to answer later queries without the solver
MODELS_KEPT = 32


class ActivationSolver:
    """One solver over the feature model's clauses, asked which elements can be active.

    It is a solver of its own (not the line's shared one), so the same line always gives
    the same answers and witnesses whatever was asked of the shared solver before.
    Queries are made cheap three ways, since on a big line each full solve costs time
    linear in the number of features: every model found is kept for a while and
    answers later queries it satisfies; a pair the feature model forbids outright
    (alternatives, ``excludes``, ``requires``) fails by unit propagation alone; and
    :meth:`decide` settles all single elements with a few models, each found with the
    literals still open as preferred phases.
    """

    def __init__(self, line: ProductLine) -> None:
        formula = line.formula
        self.cnf = formula.cnf
        self.solver = Solver(name=formula.solver_name, bootstrap_with=list(self.cnf.clauses))
        # witnesses prefer features off (small products); the solver saves the phases of
        # its last model, so they are reset before every witness is read
        self._phases = [-v for v in range(1, self.cnf.num_features + 1)]
        self._answers: dict[frozenset[int], bool] = {}
        self._models: list[list[int]] = []  # recent models, feature variables only
        self._top = max(self.solver.nof_vars(), self.cnf.num_vars)  # highest variable in use

    def close(self) -> None:
        self.solver.delete()

    def __enter__(self) -> ActivationSolver:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def literal(self, element: rm_types.ResolutionElement) -> int:
        variable = self.cnf.var[element.feature.name]
        return variable if element.activeIfSelected else -variable

    def _remember(self) -> list[int]:
        model = self.solver.get_model()[: self.cnf.num_features]
        self._models.append(model)
        del self._models[:-MODELS_KEPT]
        return model

    def decide(self, elements: list[rm_types.ResolutionElement]) -> None:
        """Settle whether each element can be active, with as few solver calls as the
        feature model allows (one per model that makes a new activation literal true)."""
        pending = {self.literal(e) for e in elements} - {
            lit for key in self._answers if len(key) == 1 for lit in key
        }
        while pending:
            literal = min(pending, key=lambda lit: (abs(lit), lit))
            pending.discard(literal)
            # every feature off unless it is an open literal: a decision on a sibling
            # then never comes first and blocks the literal the model could also cover
            phases = list(self._phases)
            for lit in pending:
                phases[abs(lit) - 1] = lit
            self.solver.set_phases(phases)
            if not self.solver.solve(assumptions=[literal]):
                self._answers[frozenset((literal,))] = False
                continue
            self._answers[frozenset((literal,))] = True
            model = self._remember()
            for lit in [lit for lit in pending if model[abs(lit) - 1] == lit]:
                self._answers[frozenset((lit,))] = True
                pending.discard(lit)

    def possible(self, *elements: rm_types.ResolutionElement) -> bool:
        """Whether one product activates all ``elements`` (asked once per literal set)."""
        assumptions = frozenset(self.literal(e) for e in elements)
        answer = self._answers.get(assumptions)
        if answer is None:
            answer = self._possible(sorted(assumptions))
            self._answers[assumptions] = answer
        return answer

    def _possible(self, literals: list[int]) -> bool:
        if any(-lit in literals for lit in literals):
            return False
        for model in reversed(self._models):
            if all(model[abs(lit) - 1] == lit for lit in literals):
                return True
        if not self.solver.propagate(assumptions=literals)[0]:
            return False
        if not self.solver.solve(assumptions=literals):
            return False
        self._remember()
        return True

    def fresh(self) -> int:
        """A variable of no feature, for the conditions of :meth:`witness_where`."""
        self._top += 1
        return self._top

    def witness_where(
        self,
        element: rm_types.ResolutionElement | None,
        clauses: list[list[int]],
        assuming: list[int] | None = None,
    ) -> tuple[str, ...] | None:
        """A product activating ``element`` (if one is given) in which ``clauses`` (over
        activation literals and :meth:`fresh` variables) hold and the literals
        ``assuming`` are true, or None. The clauses are asked about once: a selector
        variable switches them on for this question and off for good after it; the
        literals are assumptions, which leave nothing behind in the solver."""
        selector = self.fresh()
        for clause in clauses:
            self.solver.add_clause([-selector, *clause])
        self.solver.set_phases(self._phases)
        active = [] if element is None else [self.literal(element)]
        found = self.solver.solve(assumptions=[*active, *(assuming or ()), selector])
        model = self.solver.get_model()[: self.cnf.num_features] if found else None
        self.solver.add_clause([-selector])
        if model is None:
            return None
        return tuple(sorted(self.cnf.names[lit - 1] for lit in model if lit > 0))

    def witness(self, *elements: rm_types.ResolutionElement) -> tuple[str, ...] | None:
        """A product (feature names, sorted) in which all ``elements`` are active, or None.

        Only asked for what is reported: reading a whole model costs time linear in the
        number of features, which on big lines dominates the yes/no queries.
        """
        if not self.possible(*elements):
            return None
        self.solver.set_phases(self._phases)
        self.solver.solve(assumptions=sorted({self.literal(e) for e in elements}))
        model = self.solver.get_model()[: self.cnf.num_features]
        return tuple(sorted(self.cnf.names[lit - 1] for lit in model if lit > 0))
