"""False-optional features: modelled as optional, yet in every product with their parent.

Settled from the backbone and the tree where possible (core features are; children of
core parents and of subtrees no constraint touches are not), then filtered by every
model found so far, then one call ``parent and not feature`` per survivor, with the
solver steered (parents on, children off) so each model found rules out as many
pending features as it can.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from spl.resolver.analysis.cnf import FeatureModelCNF
    from spl.resolver.analysis.formula import FeatureModelFormula


def optional_features(cnf: FeatureModelCNF) -> dict[int, int]:
    """Variable -> parent's variable of every feature that may be false-optional by the
    tree alone: modelled as optional, and some constraint touches its subtree. Every
    model found removes those it shows absent beside their parent
    (``FeatureModelFormula.unrefuted``)."""
    var, parent_of = cnf.var, cnf.parent
    return {
        var[name]: var[parent]
        for name in cnf.names[1:]
        if (parent := parent_of.get(name)) is not None
        and name not in cnf.modelled_mandatory
        and name not in cnf.free_optional
    }


def false_optional(formula: FeatureModelFormula) -> list[str]:
    """The false-optional features, sorted by name.

    "Modelled as optional": not the root, not a mandatory child and not the sole
    member of a group that needs a member. Features whose parent is dead are not
    reported (they are dead themselves; the dead list names them).
    """
    cnf = formula.cnf
    core, dead = formula.backbone()
    if not formula.satisfiable():
        return []
    result: list[int] = []
    # a model found so far with the parent and without the feature disproves it: those
    # left are the candidates (each model was folded in as it was found)
    unrefuted = formula.unrefuted or {}
    pending: list[tuple[int, int]] = []
    for name in cnf.names[1:]:
        parent = cnf.parent.get(name)
        if parent is None or name in cnf.modelled_mandatory or parent in dead:
            continue
        if name in core:  # in every product, so in every product with its parent
            result.append(cnf.var[name])
            continue
        if parent in core or cnf.var[name] not in unrefuted:
            continue  # a product with the parent lacks the (non-core) feature
        pending.append((cnf.var[name], cnf.var[parent]))
    solver = formula.solver
    while pending:
        f, p = pending.pop(0)
        # prefer models with the parents on and the children off: each one found
        # then rules out as many pending features as it can
        if not solver.propagate(assumptions=[p, -f])[0]:
            result.append(f)  # as for the backbone: propagation alone settles many
            continue
        phases = {q: q for _, q in pending}
        phases.update((g, -g) for g, _ in pending)
        solver.set_phases(list(phases.values()))
        if solver.solve(assumptions=[p, -f]):
            m = formula.sample()
            pending = [(g, q) for g, q in pending if not (m[q - 1] > 0 and m[g - 1] < 0)]
        else:
            result.append(f)
    return formula.names(result)
