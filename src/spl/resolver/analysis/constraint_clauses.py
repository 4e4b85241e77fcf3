"""The clauses of one cross-tree constraint, from its formula tree.

Most real constraints (``requires``, ``excludes``, ``A => B``, ...) are one two-literal
clause and are written as such. Every other formula goes to negation normal form and is
distributed into clauses directly while that stays under :data:`DIRECT_CNF_LIMIT`
clauses (no auxiliary variables: they cost every solver call); a bigger one is split at
its top-level conjunction and each part too big to distribute gets a Tseitin variable.
The feature-model encoding (:mod:`spl.resolver.analysis.cnf`) numbers the variables and owns the
clauses; this module only turns one formula into clauses over those numbers.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from spl.resolver.analysis.cnf import Clause

# A constraint whose CNF by distribution stays under this many clauses is encoded
# directly (no auxiliary variables); bigger ones get Tseitin definitions.
DIRECT_CNF_LIMIT = 16


def constraint_clauses(tree: tuple, var: Mapping[str, int], top: int) -> tuple[list[Clause], int]:
    """The clauses of a formula tree whose features ``var`` numbers, and the highest
    variable in use after them (auxiliaries are numbered from ``top + 1``)."""
    binary = _binary_clause(tree)
    if binary is not None:
        (sign_a, name_a), (sign_b, name_b) = binary
        a = var[name_a] if sign_a else -var[name_a]
        b = var[name_b] if sign_b else -var[name_b]
        if a == b:
            return [(a,)], top
        return ([(a, b)] if a != -b else []), top
    clausifier = _Clausifier(var, top)
    nnf = clausifier.nnf(tree, True)
    try:
        clauses = _distribute(nnf)
    except _TooBig:
        clauses = []
        for part in _flat(nnf, "and"):  # a conjunction needs no variable of its own
            try:
                clauses.extend(_distribute(part))
            except _TooBig:
                clauses.append((clausifier.tseitin(part),))
    clauses.extend(clausifier.definitions)
    return _simplify(clauses), clausifier.top


class _Clausifier:
    """Negation normal form and Tseitin definitions over numbered variables."""

    def __init__(self, var: Mapping[str, int], top: int) -> None:
        self.var = var
        self.top = top
        self.definitions: list[Clause] = []
        self.aliases: dict[str, int] = {}  # defined variables standing in for operands

    def nnf(self, tree: tuple, positive: bool) -> tuple:
        """Negation normal form as nested tuples: ("lit", l) | ("and"|"or", [parts])."""
        op = tree[0]
        if op == "ref":
            v = self.aliases.get(tree[1]) or self.var[tree[1]]
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
            # each iff writes both operands twice: an operand holding another iff stands
            # in as a defined variable, or nested iffs would grow the formula 2**depth
            if _holds_iff(a):
                a = ("ref", self.define(self.nnf(a, True)))
            if _holds_iff(b):
                b = ("ref", self.define(self.nnf(b, True)))
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

    def define(self, node: tuple) -> str:
        """A name for a Tseitin literal equivalent to NNF ``node``, usable as a ``ref``."""
        name = f"\0aux{len(self.aliases)}"  # no feature is named so
        self.aliases[name] = self.tseitin(node)
        return name

    def tseitin(self, node: tuple) -> int:
        """A literal equivalent to ``node``; full equivalences keep auxiliaries determined.

        Nested operands of the same junctor share one variable (``a | (b | c)`` is one
        three-way or): the long or-chains of kernel models would otherwise get a variable
        per operator, and every solver call pays for each variable.
        """
        if node[0] == "lit":
            return node[1]
        lits = [self.tseitin(part) for part in _flat(node, node[0])]
        self.top += 1
        x = self.top
        if node[0] == "and":
            self.definitions.extend((-x, lit) for lit in lits)
            self.definitions.append((x, *(-lit for lit in lits)))
        else:
            self.definitions.append((-x, *lits))
            self.definitions.extend((x, -lit) for lit in lits)
        return x


def _holds_iff(tree: tuple) -> bool:
    stack = [tree]
    while stack:
        node = stack.pop()
        if node[0] == "iff":
            return True
        if node[0] != "ref":
            stack.extend(node[1:2] if node[0] == "not" else node[1:3])
    return False


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
