"""Checking a product selection against the feature model (docs/resolution.md, step 1).

A selection names features the user wants (and optionally features they do not want).
It is one of three things:

* **invalid** — no product contains it. The explanation is a *minimal* set of rules
  (root, tree edges, groups, cross-tree constraints) that together with a minimal part of
  the selection have no product, each printed as the author wrote it with its location:
  ``Roomba excludes AdditionalPC (mapping.fm:17:5)``. The set comes from the solver's
  unsat core over one selector literal per rule, shrunk by deletion until every rule in
  it is needed — so the user reads the reason, not the whole model.
* **complete** — the selection, completed by what it forces (root, ancestors, mandatory
  children, features forced by constraints: every feature true in *all* products
  containing the selection) and with every other feature left out, is a product.
* **incomplete** — that completion still leaves a choice open, e.g. a ``xor`` group
  with no member decided; the open choices are listed with their candidates.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal, cast

from pysat.solvers import Solver

from spl.core.diagnostics import Diagnostic, Location, ModelError
from spl.resolver.analysis.fm_rules import Rule
from spl.resolver.analysis.formula import FeatureModelFormula, formula_of
from spl.resolver.analysis.formula_trees import evaluate

if TYPE_CHECKING:
    from spl.dsl.fm.plain import FmModel

Status = Literal["complete", "incomplete", "invalid"]


@dataclass(frozen=True)
class OpenChoice:
    """A rule the completed selection does not yet satisfy, and who could satisfy it."""

    rule: Rule
    candidates: tuple[str, ...]

    def __str__(self) -> str:
        where = f" ({self.rule.location})" if self.rule.location else ""
        return f"{self.rule.text}{where}: choose among {', '.join(self.candidates)}"


@dataclass(frozen=True)
class SelectionCheck:
    status: Status
    selected: tuple[str, ...]
    deselected: tuple[str, ...]
    # the completed product (tree order); for an incomplete selection, what is forced
    features: tuple[str, ...] = ()
    added: tuple[str, ...] = ()  # forced by the selection, not given by the user
    excluded: tuple[str, ...] = ()  # ruled out by the selection, not deselected by the user
    open_choices: tuple[OpenChoice, ...] = ()
    conflict: tuple[Rule, ...] = ()  # minimal violated rules (invalid only)
    conflicting: tuple[str, ...] = ()  # minimal part of the selection in the conflict
    diagnostics: tuple[Diagnostic, ...] = field(default=())

    @property
    def valid(self) -> bool:
        return self.status != "invalid"

    @property
    def complete(self) -> bool:
        return self.status == "complete"

    def explanation(self) -> str:
        """The reason in words: the violated rules, or the open choices."""
        if self.status == "invalid":
            return "; ".join(str(rule) for rule in self.conflict)
        if self.status == "incomplete":
            return "; ".join(str(choice) for choice in self.open_choices)
        return ""

    def raise_unless_complete(self) -> None:
        if self.status != "complete":
            raise ModelError([d for d in self.diagnostics if d.severity == "error"])


# Unknown feature names get a "did you mean" for the first this many only: finding it
# compares the name with every feature's, and a selection that is not this model's
# (another line's, generated, hostile) may name thousands (200,000 took 50 s).
SUGGESTED = 20


def check_selection(
    model: FmModel | FeatureModelFormula,
    selected: Iterable[str],
    deselected: Iterable[str] = (),
    locations: Mapping[str, Location] | None = None,
    source: Location | None = None,
) -> SelectionCheck:
    """Classify a selection; ``model`` is a FeatureModel or a :class:`FeatureModelFormula`.

    ``locations`` maps a feature name to where the user wrote it (for diagnostics);
    ``source`` is where the selection as a whole comes from. Unknown or contradictory
    names raise :class:`ModelError` with every such problem.
    """
    formula = formula_of(model)
    cnf = formula.cnf
    selected = tuple(dict.fromkeys(selected))
    deselected = tuple(dict.fromkeys(deselected))
    locations = dict(locations or {})

    def where(name: str | None) -> Location | None:
        return locations.get(name, source) if name is not None else source

    problems: list[Diagnostic] = []
    unknown = [name for name in (*selected, *deselected) if name not in cnf.var]
    for index, name in enumerate(unknown):
        hint = ""
        if index < SUGGESTED:
            import difflib  # only a misspelt name needs it, not every spl start

            close = difflib.get_close_matches(name, cnf.names, n=1)
            hint = f" (did you mean {close[0]}?)" if close else ""
        problems.append(Diagnostic(where(name), f"unknown feature {name!r}{hint}"))
    for name in sorted(set(selected) & set(deselected)):
        problems.append(Diagnostic(where(name), f"feature {name} is both selected and deselected"))
    if problems:
        raise ModelError(problems)

    assumptions = [cnf.var[n] for n in selected] + [-cnf.var[n] for n in deselected]
    solver = formula.solver
    if not solver.solve(assumptions=assumptions):
        return _invalid(formula, selected, deselected, assumptions, where)

    forced = _entailed(formula, assumptions)
    tree_order = cnf.names
    chosen = {n for n in tree_order if forced.get(cnf.var[n]) is True}
    features = tuple(n for n in tree_order if n in chosen)
    given = set(selected)
    added = tuple(n for n in features if n not in given)
    excluded = tuple(
        n for n in tree_order if forced.get(cnf.var[n]) is False and n not in set(deselected)
    )
    closed_world = [cnf.var[n] if n in chosen else -cnf.var[n] for n in tree_order]
    diagnostics: list[Diagnostic] = []
    if added:
        diagnostics.append(Diagnostic(source, "added by completion: " + ", ".join(added), "info"))
    if solver.solve(assumptions=closed_world):
        return SelectionCheck(
            "complete",
            selected,
            deselected,
            features,
            added,
            excluded,
            diagnostics=tuple(diagnostics),
        )
    undecided = {n for n in tree_order if cnf.var[n] not in forced}
    choices = _open_choices(formula, chosen, undecided)
    for choice in choices:
        diagnostics.append(
            Diagnostic(
                choice.rule.location or source,
                f"open choice: {choice.rule.text}; the selection decides none of "
                f"{', '.join(choice.candidates)}",
            )
        )
    return SelectionCheck(
        "incomplete",
        selected,
        deselected,
        features,
        added,
        excluded,
        tuple(choices),
        diagnostics=tuple(diagnostics),
    )


def _entailed(formula: FeatureModelFormula, assumptions: list[int]) -> dict[int, bool]:
    """Feature variables with the same value in every product containing the selection."""
    solver = formula.solver
    n = formula.cnf.num_features
    _, propagated = solver.propagate(assumptions=assumptions)
    forced = {abs(lit): lit > 0 for lit in propagated if abs(lit) <= n}
    solver.solve(assumptions=assumptions)
    model = solver.get_model()
    candidates = {v: model[v - 1] > 0 for v in range(1, n + 1) if v not in forced}
    for v in range(1, n + 1):
        if v not in candidates:
            continue
        value = candidates.pop(v)
        if solver.solve(assumptions=[*assumptions, -v if value else v]):
            model = solver.get_model()
            candidates = {u: b for u, b in candidates.items() if (model[u - 1] > 0) == b}
        else:
            forced[v] = value
    return forced


def _open_choices(
    formula: FeatureModelFormula, chosen: set[str], undecided: set[str]
) -> list[OpenChoice]:
    choices: list[OpenChoice] = []
    for rule in formula.cnf.rules:
        if rule.kind == "group":
            parent = rule.features[0]
            members = rule.features[1:]
            lower = rule.bounds[0]
            if parent in chosen and sum(m in chosen for m in members) < lower:
                candidates = tuple(m for m in members if m in undecided)
                choices.append(OpenChoice(rule, candidates))
        elif rule.kind == "constraint" and not evaluate(cast(tuple, rule.formula), chosen):
            candidates = tuple(
                n for n in formula.cnf.names if n in undecided and n in rule.features
            )
            choices.append(OpenChoice(rule, candidates))
    return choices


def _invalid(
    formula: FeatureModelFormula,
    selected: tuple[str, ...],
    deselected: tuple[str, ...],
    assumptions: list[int],
    where: Callable[[str | None], Location | None],
) -> SelectionCheck:
    cnf = formula.cnf
    base = cnf.num_vars
    selector = {rule.index: base + 1 + rule.index for rule in cnf.rules}
    with Solver(name=formula.solver_name) as solver:
        for rule in cnf.rules:
            s = selector[rule.index]
            for clause in cnf.rule_clauses[rule.index]:
                solver.add_clause([*clause, -s])
        rules = [selector[r.index] for r in cnf.rules]
        selection = list(assumptions)

        def unsat(sel: list[int], rs: list[int]) -> bool:
            return not solver.solve(assumptions=[*sel, *rs])

        # "the root is selected" explains little; leave it out when the conflict holds
        # without it (through the parent edges of the selected features)
        without_root = [s for s in rules if s != selector[0]]
        if not unsat(selection, without_root):
            unsat(selection, rules)
        core = set(solver.get_core() or [])
        rules = [s for s in rules if s in core]
        selection = [lit for lit in selection if lit in core]
        # deletion-based shrinking: drop every rule, then every selected literal, that is
        # not needed for the conflict (re-using each smaller core the solver hands back)
        for s in list(rules):
            if s in rules and unsat(selection, [r for r in rules if r != s]):
                core = set(solver.get_core() or [])
                rules = [r for r in rules if r != s and r in core]
                selection = [lit for lit in selection if lit in core]
        for lit in list(selection):
            if lit in selection and unsat([x for x in selection if x != lit], rules):
                core = set(solver.get_core() or [])
                selection = [x for x in selection if x != lit and x in core]
                rules = [r for r in rules if r in core]
    index_of = {s: i for i, s in selector.items()}
    conflict = tuple(sorted((cnf.rules[index_of[s]] for s in rules), key=lambda r: r.index))
    conflicting = tuple(cnf.name_of(lit) for lit in selection)
    picked = [cnf.name_of(lit) for lit in selection if lit > 0]
    dropped = [cnf.name_of(lit) for lit in selection if lit < 0]
    parts = []
    if picked:
        parts.append("selecting " + ", ".join(picked))
    if dropped:
        parts.append("deselecting " + ", ".join(dropped))
    subject = " and ".join(parts) if parts else "the feature model (it has no product)"
    reason = "; ".join(str(rule) for rule in conflict)
    first = conflicting[0] if conflicting else None
    diagnostics = [Diagnostic(where(first), f"invalid selection: {subject} contradicts: {reason}")]
    return SelectionCheck(
        "invalid",
        selected,
        deselected,
        conflict=conflict,
        conflicting=conflicting,
        diagnostics=tuple(diagnostics),
    )
