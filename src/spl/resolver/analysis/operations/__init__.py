"""Feature-model analysis operations, one a module as flamapy keeps them.

Each works on one :class:`~spl.resolver.analysis.formula.FeatureModelFormula` (its CNF, its
incremental solver and the models found so far), which owns the solver and keeps every
answer: :mod:`.backbone` (core and dead features), :mod:`.false_optional`,
:mod:`.product_count` (exact projected #SAT). :mod:`.edit_classification` compares two
versions of a model (docs/evolution.md), one formula each.
"""
