"""CNF encoding of an extended feature model, with the provenance of every clause.

The encoding is the contract between the feature model and the SAT solver. Features get
the variables ``1..n`` in tree pre-order (so the numbering, and everything derived from
it, is deterministic); auxiliary variables (Tseitin definitions, cardinality encodings)
come after them. Every clause belongs to exactly one :class:`Rule` — the root, a
child-needs-parent edge, a mandatory child, a group, or a cross-tree constraint — and
the rule keeps its model element and source location, so an unsatisfiable selection can
be explained by naming the rules it violates, in the words the author wrote them.

Semantics (SPEC section 3, metamodels/fm.ecore): the root is selected; a child implies
its parent; a mandatory child is equivalent to its parent; an ``alternative`` group
needs exactly one member when its parent is selected, ``or`` at least one, a
``cardinality [l..u]`` group between ``l`` and ``u`` (``u = -1``: no upper bound).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from functools import cached_property
from typing import Any, NamedTuple

from pysat.card import CardEnc, EncType

from spl.diagnostics import Diagnostic, Location, ModelError, location_of
from spl.dsl.fm_plain import FeatureModel as PlainFeatureModel
from spl.dsl.fm_printer import format_formula

Clause = tuple[int, ...]

# Pairwise at-most-one is aux-free and propagates best; beyond this size its quadratic
# clause count loses against a sequential counter.
PAIRWISE_AMO_LIMIT = 12
# A constraint whose CNF by distribution stays under this many clauses is encoded
# directly (no auxiliary variables); bigger ones get Tseitin definitions.
DIRECT_CNF_LIMIT = 16


class Rule(NamedTuple):
    """One model element's contribution to the formula; explanations quote ``text``.

    ``features`` are the features the rule talks about: for tree rules (child, parent),
    for a group (parent, *members); for a constraint its features in first-use order.
    The wording and the location are built only when asked for, and the rule is a named
    tuple: encoding a 2500-feature model must not pay for thousands of sentences nobody
    reads.
    """

    index: int
    kind: str  # root | parent | mandatory | group | constraint
    element: Any
    features: tuple[str, ...] = ()
    bounds: tuple[int, int] = (0, -1)  # a group's (lower, upper as written, -1 = *)
    formula: tuple | None = None  # constraints: the formula as a tree of tuples

    @property
    def location(self) -> Location | None:
        """Where the rule is written (looked up on demand: most rules are never reported)."""
        where = location_of(self.element)
        if where is None and self.kind == "constraint":
            where = location_of(self.element.formula)
        return where

    @property
    def text(self) -> str:
        kind, names = self.kind, self.features
        if kind == "root":
            return f"{names[0]} is the root feature and always selected"
        if kind == "parent":
            return f"{names[0]} needs its parent {names[1]}"
        if kind == "mandatory":
            return f"{names[0]} is mandatory in {names[1]}"
        if kind == "constraint":
            return format_formula(self.element.formula)
        group = self.element
        parent, listed = names[0], ", ".join(names[1:])
        lower, upper = self.bounds
        if group_kind(group) == "alternative":
            return f"{parent}: exactly one of {listed}"
        if group_kind(group) == "or":
            return f"{parent}: at least one of {listed}"
        if upper < 0:
            return f"{parent}: at least {lower} of {listed}"
        return f"{parent}: between {lower} and {upper} of {listed}"

    def __str__(self) -> str:
        return f"{self.text} ({self.location})" if self.location else self.text


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

    @property
    def clauses(self) -> Iterator[Clause]:
        for clauses in self.rule_clauses:
            yield from clauses

    def literal(self, name: str, value: bool = True) -> int:
        return self.var[name] if value else -self.var[name]

    def name_of(self, literal: int) -> str:
        return self.names[abs(literal) - 1]


def group_kind(group: Any) -> str:
    kind = group.kind
    return kind.name if hasattr(kind, "name") else str(kind)


def group_bounds(group: Any, kind: str | None = None, n: int | None = None) -> tuple[int, int]:
    """(lower, upper) of a group, upper ``-1`` meaning unbounded."""
    n = len(group.features) if n is None else n
    kind = group_kind(group) if kind is None else kind
    if kind == "mandatory":
        return n, n
    if kind == "optional":
        return 0, n
    if kind == "alternative":
        return 1, 1
    if kind == "or":
        return 1, n
    return int(group.lower or 0), int(group.upper if group.upper is not None else -1)


def formula_tree(formula: Any) -> tuple:
    """A constraint formula as plain tuples: ("ref", name) | ("not", t) | (op, l, r).

    One pass over the pyecore objects; the CNF encoding and selection checking work on
    the tuples, which is several times faster than attribute access through pyecore.
    A plain model's trees (:mod:`spl.dsl.fm_plain`) have this shape plus a trailing
    source position per node, which everything reading trees by index ignores.
    """
    cls = type(formula).__name__
    if cls == "FeatureRef":
        return ("ref", formula.feature.name)
    if cls == "Not":
        return ("not", formula_tree(formula.operand))
    return (formula.operator, formula_tree(formula.left), formula_tree(formula.right))


def formula_features(tree: tuple) -> tuple[str, ...]:
    """The features a formula tree mentions, in first-use order (one pass: the long
    or-chains of kernel models made the recursive concatenation quadratic)."""
    found: dict[str, None] = {}
    stack = [tree]
    while stack:
        node = stack.pop()
        head = node[0]
        if head == "ref":
            found[node[1]] = None
        elif head == "not":
            stack.append(node[1])
        else:
            stack.append(node[2])
            stack.append(node[1])
    return tuple(found)


def evaluate(tree: tuple, product: set[str] | frozenset[str]) -> bool:
    """The truth of a formula tree in a product (a set of feature names)."""
    head = tree[0]
    if head == "ref":
        return tree[1] in product
    if head == "not":
        return not evaluate(tree[1], product)
    a, b = evaluate(tree[1], product), evaluate(tree[2], product)
    if head == "and":
        return a and b
    if head == "or":
        return a or b
    if head in ("implies", "requires"):
        return (not a) or b
    if head == "excludes":
        return not (a and b)
    if head == "iff":
        return a == b
    raise ValueError(f"unknown operator {head!r}")


class _Builder:
    def __init__(self, model: Any) -> None:
        self.model = model
        self.rule_data: list[tuple] = []
        self.rule_clauses: list[list[Clause]] = []
        self.modelled_mandatory: set[str] = set()
        self.definitions: list[Clause] = []
        # one pass over the pyecore tree (attribute access there is the slow part)
        root = model.root
        self.root = root
        self.names: list[str] = []
        self.parent: dict[str, str | None] = {}
        self.groups: list[tuple[str, Any, list[Any], list[str]]] = []
        stack: list[tuple[Any, str | None]] = [(root, None)]
        if isinstance(model, PlainFeatureModel):
            groups_ref = None
        else:
            # reading an unset many-valued reference makes pyecore create an empty
            # collection; asking first spares that for every leaf of a freshly loaded model
            groups_ref = root.eClass.findEStructuralFeature("groups")
        while stack:
            feature, parent = stack.pop()
            name = feature.name
            self.names.append(name)
            self.parent[name] = parent
            pushed = []
            if groups_ref is None:
                groups = feature.groups
            else:
                groups = feature.groups if feature.eIsSet(groups_ref) else ()
            for group in groups:
                children = list(group.features)
                members = [child.name for child in children]
                self.groups.append((name, group, children, members))
                pushed.extend(zip(children, [name] * len(children), strict=True))
            stack.extend(reversed(pushed))
        self.var = {name: i + 1 for i, name in enumerate(self.names)}
        self.top = len(self.names)
        if len(self.var) != len(self.names):  # the builders refuse this; a model made in
            self._refuse_duplicates(root)  # code may not have gone through them

    def _refuse_duplicates(self, root: Any) -> None:
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
        element: Any,
        features: tuple[str, ...],
        clauses: list[Clause],
        bounds: tuple[int, int] = (0, -1),
        tree: tuple | None = None,
    ) -> None:
        self.rule_data.append((kind, element, features, bounds, tree))
        self.rule_clauses.append(clauses)

    def fresh(self) -> int:
        self.top += 1
        return self.top

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
        self, parent: str, group: Any, children: list[Any], members: list[str]
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

    def encode_constraint(self, constraint: Any) -> None:
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
        binary = _binary_clause(tree)
        if binary is not None:  # most real constraints: requires, excludes, A => B, ...
            a, b = self.var[binary[0][1]], self.var[binary[1][1]]
            a, b = (a if binary[0][0] else -a), (b if binary[1][0] else -b)
            clauses = [(a, b)] if a != -b else []
            self.rule(
                "constraint",
                constraint,
                tuple(dict.fromkeys((binary[0][1], binary[1][1]))),
                [(a,)] if a == b else clauses,
                (0, -1),
                tree,
            )
            return
        nnf = self.nnf(tree, True)
        try:
            clauses = _distribute(nnf)
        except _TooBig:
            clauses = []
            for part in _flat(nnf, "and"):  # a conjunction needs no variable of its own
                try:
                    clauses.extend(_distribute(part))
                except _TooBig:
                    clauses.append((self.tseitin(part),))
            clauses.extend(self.definitions)
            self.definitions = []
        self.rule("constraint", constraint, features, _simplify(clauses), (0, -1), tree)

    # --- formulas -------------------------------------------------------------------
    def nnf(self, tree: tuple, positive: bool) -> tuple:
        """Negation normal form as nested tuples: ("lit", l) | ("and"|"or", [parts])."""
        op = tree[0]
        if op == "ref":
            v = self.var[tree[1]]
            return ("lit", v if positive else -v)
        if op == "not":
            return self.nnf(tree[1], not positive)
        a, b = tree[1], tree[2]
        if op == "and":
            parts, junctor = [self.nnf(a, positive), self.nnf(b, positive)], "and"
        elif op == "or":
            parts, junctor = [self.nnf(a, positive), self.nnf(b, positive)], "or"
        elif op in ("implies", "requires"):
            parts, junctor = [self.nnf(a, not positive), self.nnf(b, positive)], "or"
        elif op == "excludes":
            parts, junctor = [self.nnf(a, not positive), self.nnf(b, not positive)], "or"
        elif op == "iff":
            if positive:
                return (
                    "or",
                    [
                        ("and", [self.nnf(a, True), self.nnf(b, True)]),
                        ("and", [self.nnf(a, False), self.nnf(b, False)]),
                    ],
                )
            return (
                "or",
                [
                    ("and", [self.nnf(a, True), self.nnf(b, False)]),
                    ("and", [self.nnf(a, False), self.nnf(b, True)]),
                ],
            )
        else:
            raise ValueError(f"unknown operator {op!r}")
        if not positive:
            junctor = "or" if junctor == "and" else "and"
        return (junctor, parts)

    def tseitin(self, node: tuple) -> int:
        """A literal equivalent to ``node``; full equivalences keep auxiliaries determined.

        Nested operands of the same junctor share one variable (``a | (b | c)`` is one
        three-way or): the long or-chains of kernel models would otherwise get a variable
        per operator, and every solver call pays for each variable.
        """
        if node[0] == "lit":
            return node[1]
        lits = [self.tseitin(part) for part in _flat(node, node[0])]
        x = self.fresh()
        if node[0] == "and":
            self.definitions.extend((-x, lit) for lit in lits)
            self.definitions.append((x, *(-lit for lit in lits)))
        else:
            self.definitions.append((-x, *lits))
            self.definitions.extend((x, -lit) for lit in lits)
        return x


class _TooBig(Exception):
    pass


def _flat(node: tuple, junctor: str) -> list[tuple]:
    """The operands of ``node`` with nested ``junctor`` nodes opened, in order."""
    if node[0] != junctor:
        return [node]
    out: list[tuple] = []
    stack = list(reversed(node[1]))
    while stack:
        part = stack.pop()
        if part[0] == junctor:
            stack.extend(reversed(part[1]))
        else:
            out.append(part)
    return out


def _binary_clause(tree: tuple) -> tuple[tuple[bool, str], tuple[bool, str]] | None:
    """``((sign, name), (sign, name))`` when the formula is one two-literal clause."""
    op = tree[0]
    if op == "not":
        inner = tree[1]
        if inner[0] == "and" and inner[1][0] == "ref" and inner[2][0] == "ref":
            return (False, inner[1][1]), (False, inner[2][1])
        return None
    if (
        op not in ("implies", "requires", "excludes", "or")
        or tree[1][0] != "ref"
        or tree[2][0] != "ref"
    ):
        return None
    left, right = tree[1][1], tree[2][1]
    if op == "or":
        return (True, left), (True, right)
    if op == "excludes":
        return (False, left), (False, right)
    return (False, left), (True, right)


def _distribute(node: tuple) -> list[Clause]:
    if node[0] == "lit":
        return [(node[1],)]
    parts = [_distribute(part) for part in node[1]]
    if node[0] == "and":
        out = [c for part in parts for c in part]
    else:
        out = [()]
        for part in parts:
            out = [a + b for a in out for b in part]
            if len(out) > DIRECT_CNF_LIMIT:
                raise _TooBig
    if len(out) > DIRECT_CNF_LIMIT:
        raise _TooBig
    return out


def _simplify(clauses: list[Clause]) -> list[Clause]:
    """Drop duplicate literals and tautologies (``A or not A``), keeping literal order."""
    out: list[Clause] = []
    for clause in clauses:
        unique = dict.fromkeys(clause)
        if any(-lit in unique for lit in unique):
            continue  # a literal and its negation: always true
        out.append(clause if len(unique) == len(clause) else tuple(unique))
    return out


def encode(model: Any) -> FeatureModelCNF:
    """The CNF of a feature model: an ``spl.metamodels.fm`` FeatureModel (pyecore) or the
    same model held in plain objects (:mod:`spl.dsl.fm_plain`, formulas as tuple trees,
    which the encoding uses as they are)."""
    return _Builder(model).build()
