"""Analysis memory is bounded by the model, not by the solver models it finds
(docs/performance.md, "Analysis memory"): each model is folded into what the operations
need and dropped."""

from __future__ import annotations

import tracemalloc

from spl.dsl.interop.formats import load_analysable_model
from spl.resolver.analysis.formula import RECENT_MODELS, FeatureModelFormula

from support.real_models import REAL_MODELS


def test_the_backbone_and_false_optional_loops_keep_no_model_they_do_not_need() -> None:
    model = load_analysable_model(REAL_MODELS / "automotive01.uvl")
    with FeatureModelFormula(model) as formula:
        tracemalloc.start()
        try:
            core = formula.core_features()
            false_optional = formula.false_optional_features()
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
        # the answers flamapy gives (tests/resolver/test_analysis_real.py pins them all)
        assert len(core) == 94 and len(false_optional) == 61
        # keeping every model found (125 models of 2,770 variables each here) took 13.8 MB
        # of Python objects on this model; folding each one in as it is found takes 1 MB
        assert peak < 3_000_000, peak
        assert len(formula.recent) <= RECENT_MODELS
        assert all(len(m) == formula.cnf.num_features for m in formula.recent)
