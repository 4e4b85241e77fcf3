"""What an edit did to a feature model: two versions compared (docs/evolution.md).

The classification is that of Thüm, Batory and Kästner ("Reasoning about Edits to
Feature Models", ICSE 2009), over the union of the two feature sets, a feature a version
lacks being deselected in its products: a *refactoring* keeps the products, a
*generalization* only adds some, a *specialization* only removes some, an *arbitrary*
edit does both. Two SAT queries decide it, OLD and not NEW and the converse, and each
satisfiable one gives a witness product. Features are matched by the name written in
the file (the ``original_name`` an importer keeps, else the name), so a version may be
read from another format than the other.

Both versions are numbered over the union's features and each rule of a version (root,
tree edge, group, constraint; :mod:`spl.resolver.analysis.fm_rules`) is kept as clauses
in that numbering. Rules the two versions share are left out of a negation: OLD cannot
violate a rule it has, so the query grows with the edit, not with the model. A rule is
negated by its clauses (one selector a clause) when it has no auxiliary variables;
otherwise its clauses mean the rule only with their auxiliaries existentially
quantified (a cardinality group's sequential counter), and negating them clause by
clause would let the solver violate a clause by a choice of auxiliaries in a product
the rule accepts. Such a rule is negated by what it means: a group's members counted
outside its bounds, a constraint's formula negated and encoded afresh.

The number of products each way is the projected count of its query (the auxiliaries
left out), by one counter within one time bound
(:func:`~spl.resolver.analysis.operations.product_count.count_together`); a direction
without a witness counts 0 without counting. Counting the query directly, rather than
OLD minus OLD-and-NEW, costs one count a direction instead of up to three, and the
query's own units (what the edit's broken rule forces) shrink what is left to count.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from pysat.card import CardEnc, EncType
from pysat.solvers import Solver

from spl.core.diagnostics import Diagnostic, ModelError, location_of
from spl.dsl.fm.printer import quote_string
from spl.dsl.fm.vocabulary import is_feature_name
from spl.dsl.interop.interchange import written_name
from spl.resolver.analysis.constraint_clauses import constraint_clauses
from spl.resolver.analysis.formula import SOLVER_NAME, FeatureModelFormula, formula_of
from spl.resolver.analysis.operations.product_count import (
    COUNT_SECONDS,
    ProductCount,
    count_together,
)

if TYPE_CHECKING:
    from spl.dsl.fm.plain import FmModel
    from spl.resolver.analysis.cnf import Clause

# (OLD has products NEW rejects, NEW has products OLD rejects) -> the edit's class
CLASSES = {
    (False, False): "refactoring",
    (False, True): "generalization",
    (True, False): "specialization",
    (True, True): "arbitrary",
}


@dataclass(frozen=True)
class Move:
    """A feature both versions have, under another parent in NEW (None: the root)."""

    feature: str
    old_parent: str | None
    new_parent: str | None


@dataclass
class _Version:
    """One version in the union's numbering."""

    formula: FeatureModelFormula
    var: dict[str, int]  # the model's feature identifier -> union variable
    parent: dict[str, str | None]  # written name -> written name of its parent
    constraints: list[str]  # normalised text of each constraint
    plain: set[Clause] = field(default_factory=set)  # rules without auxiliaries
    parts: dict[tuple, list[Clause]] = field(default_factory=dict)  # the others, by meaning
    meanings: dict[tuple, tuple] = field(default_factory=dict)  # (kind, features, bounds, tree)
    lacks: list[int] = field(default_factory=list)  # union features it does not have

    def clauses(self) -> list[Clause]:
        out = sorted(self.plain)
        for clauses in self.parts.values():
            out.extend(clauses)
        out.extend((-v,) for v in self.lacks)
        return out


class ModelEdit:
    """Two versions of a feature model, OLD and NEW, compared; each answer computed once."""

    def __init__(
        self, old: FmModel | FeatureModelFormula, new: FmModel | FeatureModelFormula
    ) -> None:
        old_formula, new_formula = formula_of(old), formula_of(new)
        # the formulas made here are closed here; a caller's stay open for the caller
        self._made = [f for f, given in ((old_formula, old), (new_formula, new)) if f is not given]
        old_written = written_names(old_formula.model)
        new_written = written_names(new_formula.model)
        names = [old_written[name] for name in old_formula.cnf.names]
        known = set(names)
        names += [w for name in new_formula.cnf.names if (w := new_written[name]) not in known]
        self.names = names  # union variable v is the feature names[v - 1]
        self.top = len(names)
        self.old = self._number(old_formula, old_written, None)
        self.new = self._number(new_formula, new_written, self.old)
        self._witnesses: tuple[list[str] | None, list[str] | None] | None = None
        self._queries: list[list[Clause] | None] = [None, None]  # OLD and not NEW, converse

    def close(self) -> None:
        for formula in self._made:
            formula.close()

    def __enter__(self) -> ModelEdit:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- what the files say -----------------------------------------------------------
    @property
    def added(self) -> list[str]:
        return sorted(set(self.new.parent) - set(self.old.parent))

    @property
    def removed(self) -> list[str]:
        return sorted(set(self.old.parent) - set(self.new.parent))

    @property
    def moved(self) -> list[Move]:
        old, new = self.old.parent, self.new.parent
        return [
            Move(name, old[name], new[name])
            for name in sorted(set(old) & set(new))
            if old[name] != new[name]
        ]

    @property
    def constraints_added(self) -> list[str]:
        return sorted(set(self.new.constraints) - set(self.old.constraints))

    @property
    def constraints_removed(self) -> list[str]:
        return sorted(set(self.old.constraints) - set(self.new.constraints))

    # --- what the products say --------------------------------------------------------
    def witnesses(self) -> tuple[list[str] | None, list[str] | None]:
        """(a product of OLD that NEW rejects, a product of NEW that OLD rejects), each
        its selected feature names, sorted, or None when there is none."""
        if self._witnesses is None:
            self._witnesses = (
                self._witness(self.old, self.new),
                self._witness(self.new, self.old),
            )
        return self._witnesses

    @property
    def classification(self) -> str:
        old_not_new, new_not_old = self.witnesses()
        return CLASSES[(old_not_new is not None, new_not_old is not None)]

    def counts(self, seconds: float | None = COUNT_SECONDS) -> tuple[ProductCount, ProductCount]:
        """(products of OLD that NEW rejects, products of NEW that OLD rejects): each
        query's projected count, exact, or None with a note past ``seconds`` for all the
        counting (None: no time bound). A query without a witness counts 0 uncounted."""
        self.witnesses()
        asked = [query for query in self._queries if query is not None]
        started = time.monotonic()
        found = iter(count_together(asked, self._depths(), seconds))
        counts = [ProductCount(0) if query is None else next(found) for query in self._queries]
        if seconds is not None and time.monotonic() - started >= seconds:
            unknown = ProductCount(None, f"not counted within {seconds:g} s")
            counts = [unknown if count.value is None else count for count in counts]
        return counts[0], counts[1]

    # --- the numbering ----------------------------------------------------------------
    def _fresh(self) -> int:
        self.top += 1
        return self.top

    def _number(
        self, formula: FeatureModelFormula, written: dict[str, str], other: _Version | None
    ) -> _Version:
        cnf = formula.cnf
        union = {name: v for v, name in enumerate(self.names, 1)}
        var = {name: union[written[name]] for name in cnf.names}
        parent = {
            written[name]: (None if up is None else written[up]) for name, up in cnf.parent.items()
        }
        version = _Version(formula, var, parent, [])
        n = cnf.num_features
        features = [var[name] for name in cnf.names]
        for (kind, _element, members, bounds, tree), clauses in zip(
            cnf.rule_data, cnf.rule_clauses, strict=True
        ):
            if kind == "constraint":
                version.constraints.append(constraint_text(tree, written))
            if all(abs(lit) <= n for clause in clauses for lit in clause):
                version.plain.update(
                    tuple(
                        sorted(features[lit - 1] if lit > 0 else -features[-lit - 1] for lit in c)
                    )
                    for c in clauses
                )
                continue
            if kind == "constraint":
                key: tuple = (kind, version.constraints[-1])
            else:
                key = (kind, written[members[0]], tuple(sorted(written[m] for m in members[1:])))
                key += bounds
            version.meanings[key] = (kind, members, bounds, tree)
            if other is not None and key in other.parts:
                version.parts[key] = other.parts[key]  # the same rule: the same clauses
            elif key not in version.parts:
                version.parts[key] = self._renumbered(clauses, features)
        present = set(features)
        version.lacks = [v for v in range(1, len(self.names) + 1) if v not in present]
        return version

    def _renumbered(self, clauses: list[Clause], features: list[int]) -> list[Clause]:
        """A rule's clauses in the union's numbering, its auxiliaries made fresh."""
        n, base = len(features), self.top
        aux: dict[int, int] = {}
        out = []
        for clause in clauses:
            mapped = []
            for lit in clause:
                v = abs(lit)
                u = features[v - 1] if v <= n else aux.setdefault(v, base + len(aux) + 1)
                mapped.append(u if lit > 0 else -u)
            out.append(tuple(mapped))
        self.top = base + len(aux)
        return out

    # --- the queries ------------------------------------------------------------------
    def _witness(self, first: _Version, second: _Version) -> list[str] | None:
        """A product of ``first`` that ``second`` rejects; the query is kept for counting."""
        violated = self._violations(first, second)
        if violated is None:
            return None
        query = first.clauses() + violated
        with Solver(name=SOLVER_NAME, bootstrap_with=query) as solver:
            if not solver.solve():
                return None
            selected = {lit for lit in solver.get_model() if lit > 0}
        self._queries[first is self.new] = query + self._backbone(first)
        return sorted(self.names[v - 1] for v in range(1, len(self.names) + 1) if v in selected)

    def _violations(self, first: _Version, second: _Version) -> list[Clause] | None:
        """Clauses satisfiable (their fresh variables chosen) exactly where some rule of
        ``second`` that ``first`` lacks is broken, or a feature ``second`` lacks is
        selected; None when there is no such rule or feature (``first``'s products are
        all ``second``'s)."""
        present = set(first.var.values())
        either: list[int] = [v for v in second.lacks if v in present]
        extra: list[Clause] = []
        for clause in sorted(second.plain - first.plain):
            if len(clause) == 1:
                either.append(-clause[0])
                continue
            selector = self._fresh()
            extra.extend((-selector, -lit) for lit in clause)
            either.append(selector)
        for key, (kind, members, bounds, tree) in second.meanings.items():
            if key in first.parts:
                continue
            if kind == "constraint":
                clauses, self.top = constraint_clauses(("not", tree), second.var, self.top)
                either.append(self._guarded(clauses, extra))
            else:
                either.extend(self._outside(members, bounds, second.var, extra))
        if not either:
            return None
        return [*extra, tuple(either)]

    def _outside(
        self, members: tuple[str, ...], bounds: tuple[int, int], var: dict[str, int], extra: list
    ) -> list[int]:
        """Literals each true only where a group's count is outside its bounds (as
        :mod:`spl.resolver.analysis.cnf` encodes a group: the lower bound when its parent is
        selected, the upper one always)."""
        parent, lits = var[members[0]], [var[name] for name in members[1:]]
        n = len(lits)
        lower, written_upper = bounds
        upper = n if written_upper < 0 or written_upper > n else written_upper
        if lower > n or lower > upper:
            return [parent]  # the encoding forbids the parent
        out = []
        if lower >= 1:
            few = CardEnc.atmost(
                lits=lits, bound=lower - 1, top_id=self.top, encoding=EncType.seqcounter
            )
            self.top = max(self.top, few.nv)
            selector = self._guarded([tuple(c) for c in few.clauses], extra)
            extra.append((-selector, parent))
            out.append(selector)
        if upper < n:
            many = CardEnc.atleast(
                lits=lits, bound=upper + 1, top_id=self.top, encoding=EncType.seqcounter
            )
            self.top = max(self.top, many.nv)
            out.append(self._guarded([tuple(c) for c in many.clauses], extra))
        return out

    def _guarded(self, clauses: list[Clause], extra: list[Clause]) -> int:
        """A selector implying ``clauses`` (added to ``extra``)."""
        selector = self._fresh()
        extra.extend((-selector, *clause) for clause in clauses)
        return selector

    # --- counting ---------------------------------------------------------------------
    def _backbone(self, version: _Version) -> list[Clause]:
        """Core and dead features as units: implied, and they shrink every component the
        counter meets (:mod:`spl.resolver.analysis.operations.product_count`)."""
        core, dead = version.formula.backbone()
        units: list[Clause] = [(version.var[name],) for name in sorted(core)]
        return units + [(-version.var[name],) for name in sorted(dead)]

    def _depths(self) -> list[int]:
        depth: dict[str, int] = {}
        for version in (self.old, self.new):
            for name, up in version.parent.items():  # pre-order: parents come first
                depth.setdefault(name, 0 if up is None else depth[up] + 1)
        return [depth[name] for name in self.names]


def written_names(model: Any) -> dict[str, str]:
    """Each feature's identifier -> the name its file writes (importers keep a name
    .fm cannot carry in ``original_name``, :mod:`spl.dsl.interop.interchange`). Features
    are matched by these names, so two features of one model may not share one."""
    out: dict[str, str] = {}
    owner: dict[str, Any] = {}
    problems = []
    stack = [model.root]
    while stack:
        feature = stack.pop()
        written = written_name(feature)
        if written in owner:
            problems.append(
                Diagnostic(
                    location_of(feature),
                    f"features {owner[written].name} and {feature.name} are both named "
                    f"{written!r} (an original_name attribute): versions could not be "
                    "compared feature by feature",
                )
            )
        owner[written] = feature
        out[feature.name] = written
        children = [child for group in feature.groups for child in group.features]
        stack.extend(reversed(children))  # pre-order: the later of two is reported
    if problems:
        raise ModelError(problems)
    return out


def constraint_text(tree: tuple, written: dict[str, str]) -> str:
    """A constraint in one normal form, so two versions' constraints compare as text:
    .fm syntax, written names, ``requires`` and ``excludes`` as ``=>``, and the operands
    of an ``and`` or ``or`` chain in sorted order."""
    return _text(tree, written)[0]


def _text(tree: tuple, written: dict[str, str]) -> tuple[str, int]:
    """(text, precedence level: <=> 0, => 1, or 2, and 3, not 4, name 5)."""
    op = tree[0]
    if op == "ref":
        name = written.get(tree[1], tree[1])
        return (name if is_feature_name(name) else quote_string(name)), 5
    if op == "not":
        inner, level = _text(tree[1], written)
        return "not " + (inner if level >= 4 else f"({inner})"), 4
    if op in ("and", "or"):
        level = 3 if op == "and" else 2
        operands, stack = [], [tree]
        while stack:
            node = stack.pop()
            if node[0] == op:
                stack.extend((node[1], node[2]))
            else:
                operand, binds = _text(node, written)
                operands.append(f"({operand})" if binds <= level else operand)
        return f" {op} ".join(sorted(operands)), level
    right_tree = ("not", tree[2]) if op == "excludes" else tree[2]
    left, left_level = _text(tree[1], written)
    right, right_level = _text(right_tree, written)
    if op == "iff":
        return f"{left} <=> " + (f"({right})" if right_level <= 0 else right), 0
    left = f"({left})" if left_level <= 1 else left
    return f"{left} => " + (f"({right})" if right_level < 1 else right), 1
