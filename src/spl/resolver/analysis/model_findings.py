"""What ``spl check`` finds in a feature model checked on its own (docs/commands.md,
"spl check"): a void model, which no product satisfies, is an error at its root; a dead
feature, which no product contains, a warning at its declaration.

They are the answers ``spl analyze`` gives (docs/analysis.md), from the same solvers: the
SAT path for a Boolean model, z3 for a UVL model of the Arithmetic or Type level, so a
feature an equation kills is reported as a Boolean constraint's would be. Names are as
the file writes them (docs/fm.md, "Interchange"), and a feature of an imported UVL
model is located in its own file.
"""

from __future__ import annotations

from typing import Any

from spl.core.diagnostics import Diagnostic, location_of
from spl.dsl.fm.language import all_features
from spl.dsl.interop.interchange import written_names
from spl.dsl.interop.uvl_typed import is_typed


def feature_model_findings(model: Any) -> list[Diagnostic]:
    """The void model's error, else a warning for each dead feature, in file order."""
    if is_typed(model):
        from spl.resolver.analysis.smt import SmtFormula

        solver: Any = SmtFormula(model)
    else:
        from spl.resolver.analysis.formula import FeatureModelFormula

        solver = FeatureModelFormula(model)
    with solver as formula:
        if not formula.satisfiable():
            return [void_model(model)]
        dead = set(formula.dead_features())
    written = written_names(model)
    return [
        Diagnostic(
            location_of(feature),
            f"feature {written[feature.name]} is dead: no product of the model contains it",
            "warning",
        )
        for feature in all_features(model)
        if feature.name in dead
    ]


def void_model(model: Any) -> Diagnostic:
    """No product at all: its tree, groups and constraints contradict each other."""
    name = getattr(model, "written_name", model.name)
    return Diagnostic(
        location_of(model.root),
        f"feature model {name} has no product: its tree, groups and constraints "
        "contradict each other (the model is void, every feature dead)",
    )
