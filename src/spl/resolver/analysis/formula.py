"""Automated analysis of feature models with a CDCL SAT solver.

Solver choice: Glucose 4 through python-sat. The analyses here are hundreds of small
*incremental* queries on one formula ("is there a product without feature f?"), each
answered under assumptions on the same clause database, which keeps its learnt clauses
across calls. Glucose answers such easy queries in microseconds and supports everything
the operations and :mod:`spl.resolver.resolution.selection` need: assumptions, unsat cores over
assumptions (minimal explanations), ``propagate`` without search, and user-preferred
phases, which the backbone loop relies on. CaDiCaL 1.9.5 is the stronger solver on hard
single instances, but feature models are easy instances and CaDiCaL does not follow
preferred phases the same way: on automotive01 the same backbone + false-optional loop
needs 706 models and 197 ms with CaDiCaL against 118 models and 56 ms with Glucose 4
(``bench/fm_analysis.py --solver cadical195`` runs the comparison end to end).

Everything is computed from one :class:`FeatureModelFormula`, which owns one solver and
keeps each answer; the operations are modules of their own
(:mod:`spl.resolver.analysis.operations`): backbone (core and dead features), false-optional
features, exact product counting. Each later operation starts from what the earlier
ones left: the models found filter its candidates before the solver is asked.

Memory is bounded by the model, not by the number of solver models found: a model is
folded, as it is found, into what the operations need of it (the literals every model
so far agrees on, the optional features no model so far has shown absent beside their
parent, the last few models for the configurator) and dropped. Keeping every model
took 2.2 GB on an 18,616-feature model (docs/performance.md, "Analysis memory").
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterator
from typing import TYPE_CHECKING

from pysat.solvers import Solver

from spl.core.cyclic_gc import without_cyclic_gc
from spl.resolver.analysis.cnf import FeatureModelCNF, encode
from spl.resolver.analysis.operations.backbone import backbone
from spl.resolver.analysis.operations.false_optional import false_optional, optional_features
from spl.resolver.analysis.operations.product_count import (
    COUNT_CACHED_CLAUSES,
    COUNT_SECONDS,
    ProductCount,
    product_count,
)

if TYPE_CHECKING:
    from spl.dsl.fm.plain import FmModel

SOLVER_NAME = "glucose4"
# Models the configurator starts from (spl.resolver.analysis.configuration.Propagator).
RECENT_MODELS = 8


class FeatureModelFormula:
    """A feature model and one incremental SAT solver over its CNF; reuse it for queries."""

    def __init__(self, model: FmModel, solver_name: str = SOLVER_NAME) -> None:
        self.model = model
        with without_cyclic_gc():  # the encoding allocates only acyclic tuples
            self.cnf: FeatureModelCNF = encode(model)
        self.solver_name = solver_name
        self.solver = Solver(name=solver_name, bootstrap_with=list(self.cnf.clauses))
        self._satisfiable: bool | None = None
        self._backbone: tuple[frozenset[str], frozenset[str]] | None = None
        self._false_optional: list[str] | None = None
        # the feature part of the latest models found (``model[v - 1]`` is ``v`` or ``-v``)
        self.recent: deque[list[int]] = deque(maxlen=RECENT_MODELS)
        # feature literals every model found so far has (None: no model yet)
        self.agreed: set[int] | None = None
        # optional feature -> parent, for features no model found so far has shown absent
        # with their parent present (None: no model yet); see operations.false_optional
        self.unrefuted: dict[int, int] | None = None

    # --- plumbing -------------------------------------------------------------------
    def close(self) -> None:
        self.solver.delete()

    def __enter__(self) -> FeatureModelFormula:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def sample(self) -> list[int]:
        """The feature part of the solver's current model, folded into what later
        operations filter their candidates with before asking the solver."""
        model = self.solver.get_model()[: self.cnf.num_features]
        self.recent.append(model)
        if self.agreed is None:
            self.agreed = set(model)
            self.unrefuted = optional_features(self.cnf)
        else:
            self.agreed = {lit for lit in self.agreed if model[abs(lit) - 1] == lit}
        pending = self.unrefuted
        if pending:
            self.unrefuted = {
                f: p for f, p in pending.items() if not (model[p - 1] > 0 and model[f - 1] < 0)
            }
        return model

    def names(self, variables: set[int] | list[int]) -> list[str]:
        """Feature names of variables, sorted by name (the order every report uses)."""
        return sorted(self.cnf.names[v - 1] for v in variables)

    # --- operations (each answer computed once) -------------------------------------
    def satisfiable(self) -> bool:
        if self._satisfiable is None:
            self._satisfiable = bool(self.solver.solve())
            if self._satisfiable:
                self.sample()
        return self._satisfiable

    def backbone(self) -> tuple[frozenset[str], frozenset[str]]:
        """(core, dead): features in every product, features in none
        (:mod:`spl.resolver.analysis.operations.backbone`)."""
        if self._backbone is None:
            self._backbone = backbone(self)
        return self._backbone

    def core_features(self) -> list[str]:
        return sorted(self.backbone()[0])

    def dead_features(self) -> list[str]:
        return sorted(self.backbone()[1])

    def false_optional_features(self) -> list[str]:
        """Features modelled as optional that every product with their parent contains
        (:mod:`spl.resolver.analysis.operations.false_optional`)."""
        if self._false_optional is None:
            self._false_optional = false_optional(self)
        return self._false_optional

    def count(
        self, seconds: float | None = COUNT_SECONDS, cached_clauses: int = COUNT_CACHED_CLAUSES
    ) -> ProductCount:
        """The exact number of products, or ``None`` when a bound is exceeded (``seconds``
        None: no time bound, only the memory one;
        :mod:`spl.resolver.analysis.operations.product_count`)."""
        return product_count(self, seconds, cached_clauses)

    def products(self) -> Iterator[frozenset[str]]:
        """Every product once, as a set of feature names (a separate solver blocks them)."""
        cnf = self.cnf
        n = cnf.num_features
        with Solver(name=self.solver_name, bootstrap_with=list(cnf.clauses)) as solver:
            while solver.solve():
                model = solver.get_model()[:n]
                yield frozenset(cnf.names[lit - 1] for lit in model if lit > 0)
                solver.add_clause([-lit for lit in model])


def formula_of(model_or_formula: FmModel | FeatureModelFormula) -> FeatureModelFormula:
    if isinstance(model_or_formula, FeatureModelFormula):
        return model_or_formula
    return FeatureModelFormula(model_or_formula)


def is_satisfiable(model: FmModel | FeatureModelFormula) -> bool:
    """Whether the feature model (or :class:`FeatureModelFormula`) has a product."""
    return formula_of(model).satisfiable()


def core_features(model: FmModel | FeatureModelFormula) -> list[str]:
    return formula_of(model).core_features()


def dead_features(model: FmModel | FeatureModelFormula) -> list[str]:
    return formula_of(model).dead_features()


def false_optional_features(model: FmModel | FeatureModelFormula) -> list[str]:
    return formula_of(model).false_optional_features()


def count_products(
    model: FmModel | FeatureModelFormula, seconds: float | None = COUNT_SECONDS
) -> ProductCount:
    return formula_of(model).count(seconds)


def enumerate_products(model: FmModel | FeatureModelFormula) -> Iterator[frozenset[str]]:
    return formula_of(model).products()
