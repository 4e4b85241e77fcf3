"""CNF encoding of an extended feature model, with the provenance of every clause.

The encoding is the contract between the feature model and the SAT solver. Features get
the variables ``1..n`` in tree pre-order (so the numbering, and everything derived from
it, is deterministic); auxiliary variables (Tseitin definitions, cardinality encodings)
come after them. Every clause belongs to exactly one rule
(:class:`~spl.resolver.analysis.fm_rules.Rule`:
the root, a child-needs-parent edge, a mandatory child, a group, or a cross-tree
constraint), so an unsatisfiable selection can be explained in the author's words.
Tree and groups are encoded here; a cross-tree constraint's clauses come from
:mod:`spl.resolver.analysis.constraint_clauses`.

Semantics (docs/fm.md, "The tree" and "Constraints"; src/spl/metamodels/fm.ecore): the root is
selected; a child implies its parent; a mandatory child is equivalent to its parent; an
``alternative`` group needs exactly one member when its parent is selected, ``or`` at
least one, a ``cardinality [l..u]`` group between ``l`` and ``u`` (``u = -1``: no upper
bound).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, cast

from pysat.card import CardEnc, EncType

from spl.core.diagnostics import Diagnostic, ModelError, location_of
from spl.dsl.fm.plain import FeatureModel as PlainFeatureModel
from spl.dsl.fm.printer import format_formula
from spl.resolver.analysis.constraint_clauses import constraint_clauses
from spl.resolver.analysis.fm_rules import Rule, group_bounds, group_kind
from spl.resolver.analysis.formula_trees import formula_features, formula_tree

if TYPE_CHECKING:
    from spl.dsl.fm.plain import FmConstraint, FmFeature, FmGroup, FmModel
    from spl.metamodels import fm_types

Clause = tuple[int, ...]

# Pairwise at-most-one is aux-free and propagates best; beyond this size its quadratic
# clause count loses against a sequential counter.
PAIRWISE_AMO_LIMIT = 12


@dataclass
class FeatureModelCNF:
    """The feature model as clauses over numbered variables, grouped by rule."""

    names: list[str]  # names[v - 1] is the feature of variable v
    var: dict[str, int]  # feature name -> variable
    parent: dict[str, str | None]
    modelled_mandatory: set[str]  # mandatory child, or sole member of a group with lower >= 1
    # (kind, element, features, bounds, formula) per rule: Rule objects are made on demand
    rule_data: list[tuple]
    rule_clauses: list[list[Clause]]  # rule_clauses[rule.index]
    num_vars: int  # features and auxiliary variables
    # children of optional groups whose whole subtree no constraint mentions: dropping such
    # a subtree from a product leaves a product, so none of them is false-optional
    free_optional: set[str]

    @cached_property
    def rules(self) -> list[Rule]:
        return [Rule(i, *data) for i, data in enumerate(self.rule_data)]

    @property
    def num_features(self) -> int:
        return len(self.names)

    @cached_property
    def occurrences(self) -> tuple[list[Clause], list[list[int]]]:
        """Every clause, and per variable the numbers of the clauses it occurs in: what
        the configurator's counts gather from (``count_with_fixed``), built once per
        formula and kept with it."""
        clauses = list(self.clauses)
        occurs: list[list[int]] = [[] for _ in range(self.num_vars + 1)]
        for number, clause in enumerate(clauses):
            for lit in clause:
                occurs[abs(lit)].append(number)
        return clauses, occurs

    @property
    def clauses(self) -> Iterator[Clause]:
        for clauses in self.rule_clauses:
            yield from clauses

    def literal(self, name: str, value: bool = True) -> int:
        return self.var[name] if value else -self.var[name]

    def name_of(self, literal: int) -> str:
        return self.names[abs(literal) - 1]


class _Builder:
    def __init__(self, model: FmModel) -> None:
        self.model = model
        self.rule_data: list[tuple] = []
        self.rule_clauses: list[list[Clause]] = []
        self.modelled_mandatory: set[str] = set()
        # one pass over the pyecore tree (attribute access there is the slow part)
        root = cast("FmFeature", model.root)  # a model read has its root
        self.root = root
        self.names: list[str] = []
        self.parent: dict[str, str | None] = {}
        self.groups: list[tuple[str, FmGroup, list[FmFeature], list[str]]] = []
        stack: list[tuple[FmFeature, str | None]] = [(root, None)]
        if isinstance(model, PlainFeatureModel):
            groups_ref = None
        else:
            # reading an unset many-valued reference makes pyecore create an empty
            # collection; asking first spares that for every leaf of a freshly loaded model
            groups_ref = cast("fm_types.Feature", root).eClass.findEStructuralFeature("groups")
        while stack:
            feature, parent = stack.pop()
            name = feature.name
            self.names.append(name)
            self.parent[name] = parent
            pushed: list[tuple[FmFeature, str]] = []
            groups: Iterable[FmGroup]
            if groups_ref is None:
                groups = feature.groups
            else:
                ecore = cast("fm_types.Feature", feature)
                groups = ecore.groups if ecore.eIsSet(groups_ref) else ()
            for group in groups:
                children: list[FmFeature] = list(group.features)
                members = [child.name for child in children]
                self.groups.append((name, group, children, members))
                pushed.extend(zip(children, [name] * len(children), strict=True))
            stack.extend(reversed(pushed))
        self.var = {name: i + 1 for i, name in enumerate(self.names)}
        self.top = len(self.names)
        if len(self.var) != len(self.names):  # the builders refuse this; a model made in
            self._refuse_duplicates(root)  # code may not have gone through them

    def _refuse_duplicates(self, root: FmFeature) -> None:
        seen: set[str] = set()
        problems = []
        stack = [root]
        while stack:
            feature = stack.pop()
            if feature.name in seen:
                problems.append(
                    Diagnostic(location_of(feature), f"feature {feature.name} is defined twice")
                )
            seen.add(feature.name)
            children = [child for group in feature.groups for child in group.features]
            stack.extend(reversed(children))  # pre-order: the later definition is reported
        raise ModelError(problems)

    def rule(
        self,
        kind: str,
        element: FmFeature | FmGroup | FmConstraint,
        features: tuple[str, ...],
        clauses: list[Clause],
        bounds: tuple[int, int] = (0, -1),
        tree: tuple | None = None,
    ) -> None:
        self.rule_data.append((kind, element, features, bounds, tree))
        self.rule_clauses.append(clauses)

    def build(self) -> FeatureModelCNF:
        self.rule("root", self.root, (self.names[0],), [(1,)])
        for parent, group, children, members in self.groups:
            self.encode_group(parent, group, children, members)
        for constraint in self.model.constraints:
            self.encode_constraint(constraint)
        return FeatureModelCNF(
            self.names,
            self.var,
            self.parent,
            self.modelled_mandatory,
            self.rule_data,
            self.rule_clauses,
            self.top,
            self.free_optional(),
        )

    def free_optional(self) -> set[str]:
        touched = {
            name
            for kind, _, names, _, _ in self.rule_data
            if kind == "constraint"
            for name in names
        }
        for name in reversed(self.names):  # children before their parents
            parent = self.parent[name]
            if name in touched and parent is not None:
                touched.add(parent)
        return {
            name
            for parent, group, _, members in self.groups
            if group_kind(group) == "optional"
            for name in members
            if name not in touched
        }

    def encode_group(
        self, parent: str, group: FmGroup, children: list[FmFeature], members: list[str]
    ) -> None:
        p = self.var[parent]
        var = self.var
        lits = [var[name] for name in members]
        kind = group_kind(group)
        rule = self.rule
        self.rule_data.extend(
            ("parent", child, (name, parent), (0, -1), None)
            for child, name in zip(children, members, strict=True)
        )
        self.rule_clauses.extend([(-lit, p)] for lit in lits)
        if kind == "optional" or not lits:
            return
        if kind == "mandatory":
            for child, name, lit in zip(children, members, lits, strict=True):
                self.modelled_mandatory.add(name)
                rule("mandatory", child, (name, parent), [(-p, lit)])
            return
        lower, written_upper = group_bounds(group, kind, len(lits))
        n = len(lits)
        upper = n if written_upper < 0 or written_upper > n else written_upper
        if lower >= 1 and n == 1:
            self.modelled_mandatory.add(members[0])
        clauses: list[Clause] = []
        if lower > n or lower > upper:
            clauses.append((-p,))
        else:
            if lower == 1:
                clauses.append((-p, *lits))
            elif lower > 1:
                enc = CardEnc.atleast(
                    lits=lits, bound=lower, top_id=self.top, encoding=EncType.seqcounter
                )
                self.top = max(self.top, enc.nv)
                clauses.extend((-p, *c) for c in enc.clauses)
            if upper < n:
                # unconditional: with the parent off every member is off, which satisfies it
                clauses.extend(self.at_most(lits, upper))
        rule("group", group, (parent, *members), clauses, (lower, written_upper))

    def at_most(self, lits: list[int], bound: int) -> list[Clause]:
        if bound == 0:
            return [(-lit,) for lit in lits]
        if bound == 1 and len(lits) <= PAIRWISE_AMO_LIMIT:
            return [(-a, -b) for i, a in enumerate(lits) for b in lits[i + 1 :]]
        enc = CardEnc.atmost(lits=lits, bound=bound, top_id=self.top, encoding=EncType.seqcounter)
        self.top = max(self.top, enc.nv)
        return [tuple(c) for c in enc.clauses]

    def encode_constraint(self, constraint: FmConstraint) -> None:
        formula = constraint.formula
        tree = formula if isinstance(formula, tuple) else formula_tree(formula)
        features = formula_features(tree)
        unknown = [name for name in features if name not in self.var]
        if unknown:
            raise ModelError(
                [
                    Diagnostic(
                        location_of(constraint),
                        f"constraint {format_formula(constraint.formula)} names {name}, "
                        "which is not a feature of the tree",
                    )
                    for name in unknown
                ]
            )
        clauses, self.top = constraint_clauses(tree, self.var, self.top)
        self.rule("constraint", constraint, features, clauses, (0, -1), tree)


def encode(model: FmModel) -> FeatureModelCNF:
    """The CNF of a feature model: an ``spl.metamodels.fm`` FeatureModel (pyecore) or the
    same model held in plain objects (:mod:`spl.dsl.fm.plain`, formulas as tuple trees,
    which the encoding uses as they are)."""
    return _Builder(model).build()
