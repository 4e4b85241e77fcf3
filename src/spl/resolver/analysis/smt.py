"""Analysis of the Arithmetic and Type levels of UVL on an SMT solver (z3).

A :class:`~spl.dsl.interop.uvl_typed.TypedFeatureModel` is encoded as the Boolean model
is (:func:`spl.resolver.analysis.cnf.encode`: the same tree, groups and Boolean
constraints, as Boolean variables), plus what SAT cannot carry: a typed feature's value,
a cloned feature's instance count and every equation, with docs/fm.md's semantics
("Typed features, cardinalities and arithmetic"):

* a deselected typed feature has the value 0 (Integer, Real) or ``""`` (String); so has
  an attribute of a deselected feature, and ``sum`` and ``avg`` leave deselected
  features out (``avg`` of none selected makes its comparison false);
* numbers are rationals: ``/`` divides exactly, and a comparison whose expression
  divides by zero is false;
* a Boolean feature where a number is expected is 1 when selected, 0 when not; an
  attribute named in an equation but given no value is a variable;
* a feature with cardinality ``[a..b]`` is selected with ``a..b`` instances (``b``
  ``*``: any number from ``a``), or not at all; instances are not told apart, so a
  product is the set of selected features, and counting counts those.

:class:`SmtFormula` answers what :class:`~spl.resolver.analysis.formula.FeatureModelFormula`
answers for a Boolean model (``spl analyze`` uses either), by one incremental solver.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from fractions import Fraction
from typing import Any

import z3  # type: ignore[import-untyped]  # z3-solver ships no stubs

from spl.dsl.interop.uvl_typed import TypedFeatureModel
from spl.resolver.analysis.cnf import FeatureModelCNF, encode
from spl.resolver.analysis.operations.product_count import ProductCount

_DEFAULTS = {"Integer": 0, "Real": 0, "String": ""}


class SmtFormula:
    """One typed model on one z3 solver; every answer computed once."""

    def __init__(self, model: TypedFeatureModel) -> None:
        self.model = model
        self.cnf: FeatureModelCNF = encode(model)
        cnf = self.cnf
        self.solver = z3.Solver()
        # random phases (from z3's fixed seed: the same run each time): each product found
        # then settles about half the features still pending, not only those it must
        self.solver.set("phase_selection", 5)
        self.bools = [z3.Bool(f"b{v}") for v in range(cnf.num_vars + 1)]
        bools = self.bools
        self.solver.add(
            *(
                z3.Or([bools[lit] if lit > 0 else z3.Not(bools[-lit]) for lit in clause])
                for clause in cnf.clauses
            )
        )
        self.values: dict[str, Any] = {}
        for number, (name, kind) in enumerate(sorted(model.types.items())):
            make = {"Integer": z3.Int, "Real": z3.Real, "String": z3.String}[kind]
            value = make(f"v{number}")
            self.values[name] = value
            self.solver.add(z3.Or(self.selected(name), value == _DEFAULTS[kind]))
        for number, (name, (lower, upper, _)) in enumerate(sorted(model.cardinalities.items())):
            instances = z3.Int(f"n{number}")
            bounds = [instances >= lower] + ([instances <= upper] if upper != -1 else [])
            self.solver.add(z3.If(self.selected(name), z3.And(bounds), instances == 0))
        self.free: dict[tuple[str, str], Any] = {}
        for equation in model.equations:
            self.solver.add(self.condition(equation.formula))
        self._satisfiable: bool | None = None
        self._backbone: tuple[set[str], set[str]] | None = None
        self._false_optional: list[str] | None = None
        self._boolean_false_optional: set[str] = set()
        self._unrefuted: set[str] = set()

    def __enter__(self) -> SmtFormula:
        return self

    def __exit__(self, *exc: object) -> None:
        return None

    def selected(self, name: str) -> Any:
        return self.bools[self.cnf.var[name]]

    # -- equations as z3 terms (post-order with explicit stacks: any chain length) ------
    def condition(self, root: tuple) -> Any:
        def build(node: tuple, operands: list[Any]) -> Any:
            head = node[0]
            if head == "ref":
                return self.selected(node[1])
            if head == "cmp":
                return self.comparison(node)
            if head == "not":
                return z3.Not(operands[0])
            left, right = operands
            if head == "and":
                return z3.And(left, right)
            if head == "or":
                return z3.Or(left, right)
            if head == "implies":
                return z3.Implies(left, right)
            return left == right  # iff

        return _post_order(root, _conditions, build)

    def comparison(self, node: tuple) -> Any:
        """``left op right``, false where it divides by zero."""
        divisors: list[Any] = []
        left = self.term(node[2], divisors)
        right = self.term(node[3], divisors)
        compared = {
            "==": lambda: left == right,
            "!=": lambda: left != right,
            "<": lambda: left < right,
            "<=": lambda: left <= right,
            ">": lambda: left > right,
            ">=": lambda: left >= right,
        }[node[1]]()
        return z3.And(*(d != 0 for d in divisors), compared) if divisors else compared

    def term(self, root: tuple, divisors: list[Any]) -> Any:
        """A number as a z3 Real (or a string as a z3 String); divisors met are listed."""

        def build(node: tuple, operands: list[Any]) -> Any:
            head = node[0]
            if head == "num":
                return z3.RealVal(Fraction(node[1]))
            if head == "str":
                return z3.StringVal(node[1])
            if head == "value":
                value = self.values[node[1]]
                return z3.ToReal(value) if value.sort() == z3.IntSort() else value
            if head == "selected":
                return z3.If(self.selected(node[1]), z3.RealVal(1), z3.RealVal(0))
            if head == "attr":
                return self.attribute(node)
            if head == "arith":
                left, right = operands
                if node[1] == "/":
                    divisors.append(right)
                    return left / right
                return {"+": left + right, "-": left - right, "*": left * right}[node[1]]
            if head == "len":
                return z3.ToReal(z3.Length(operands[0]))
            if head == "floor":
                return z3.ToReal(z3.ToInt(operands[0]))
            if head == "ceil":
                return -z3.ToReal(z3.ToInt(-operands[0]))
            zero = z3.RealVal(0)
            chosen = [self.selected(f) for f, _ in node[1]]
            total = z3.Sum([z3.If(c, v, zero) for c, v in zip(chosen, operands, strict=True)])
            if head == "sum":
                return total
            count = z3.Sum([z3.If(c, z3.RealVal(1), zero) for c in chosen])
            divisors.append(count)
            return total / count

        return _post_order(root, _terms, build)

    def attribute(self, node: tuple) -> Any:
        _, feature, name, sort, value, _ = node
        if value is None:  # declared without a value: a variable, 0 or "" when deselected
            key = (feature, name)
            if key not in self.free:
                variable = (z3.String if sort == "str" else z3.Real)(f"a{len(self.free)}")
                self.free[key] = variable
                zero = z3.StringVal("") if sort == "str" else z3.RealVal(0)
                self.solver.add(z3.Or(self.selected(feature), variable == zero))
            return self.free[key]
        if sort == "str":
            written = z3.StringVal(value)
            return z3.If(self.selected(feature), written, z3.StringVal(""))
        return z3.If(self.selected(feature), z3.RealVal(Fraction(value)), z3.RealVal(0))

    # -- analyses ------------------------------------------------------------------------
    def check(self, *assumptions: Any) -> z3.ModelRef | None:
        if self.solver.check(*assumptions) == z3.sat:
            return self.solver.model()
        return None

    def satisfiable(self) -> bool:
        if self._satisfiable is None:
            self._satisfiable = self.check() is not None
        return self._satisfiable

    def boolean_answers(self) -> tuple[set[str], set[str], set[str]]:
        """(core, dead, false-optional) of the Boolean level alone, on SAT: the typed
        model's products are some of its products, so each of these holds for the
        typed model too (a false-optional one while its parent is not dead) and needs
        no SMT call."""
        from spl.resolver.analysis.formula import FeatureModelFormula

        with FeatureModelFormula(self.model) as boolean:
            return (
                set(boolean.core_features()),
                set(boolean.dead_features()),
                set(boolean.false_optional_features()),
            )

    def backbone(self) -> tuple[set[str], set[str]]:
        """(core, dead): what SAT settles on the Boolean level, then one SMT call per
        feature no product found so far settles."""
        if self._backbone is None:
            names = self.cnf.names
            if not self.satisfiable():
                self._backbone = (set(), set(names))
                return self._backbone
            core, dead, self._boolean_false_optional = self.boolean_answers()
            maybe_core = set(names) - core - dead
            maybe_dead = set(maybe_core)
            parent = self.cnf.parent
            # optional features no product found so far shows absent beside its parent
            self._unrefuted = {n for n in maybe_core if parent.get(n) is not None}

            def seen(found: z3.ModelRef) -> None:
                """Fold a product in; only the features still pending are looked up (one
                call into z3 each)."""
                asked = maybe_core | maybe_dead | self._unrefuted
                asked |= {p for n in self._unrefuted if (p := parent[n]) is not None}
                chosen = {
                    name
                    for name in asked
                    if z3.is_true(found.eval(self.selected(name), model_completion=True))
                }
                maybe_core.difference_update(asked - chosen)
                maybe_dead.difference_update(chosen)
                self._unrefuted -= {
                    n for n in self._unrefuted if n not in chosen and parent[n] in chosen
                }

            seen(self.check())
            for name in names:
                for pending, settled, literal in (
                    (maybe_core, core, z3.Not(self.selected(name))),
                    (maybe_dead, dead, self.selected(name)),
                ):
                    if name in pending:
                        found = self.check(literal)
                        if found is None:
                            settled.add(name)
                        else:
                            seen(found)
            self._backbone = (core, dead)
        return self._backbone

    def core_features(self) -> list[str]:
        return sorted(self.backbone()[0])

    def dead_features(self) -> list[str]:
        return sorted(self.backbone()[1])

    def false_optional_features(self) -> list[str]:
        """Modelled as optional, yet in every product with their parent (as
        :mod:`spl.resolver.analysis.operations.false_optional` defines it): the Boolean
        level's, then one SMT call per candidate no product found so far refutes."""
        if self._false_optional is None:
            cnf = self.cnf
            core, dead = self.backbone()
            found: list[str] = []
            if self.satisfiable():
                for name in cnf.names[1:]:
                    parent = cnf.parent.get(name)
                    if parent is None or name in cnf.modelled_mandatory or parent in dead:
                        continue
                    if (
                        name in core
                        or name in self._boolean_false_optional
                        or (
                            parent not in core
                            and name in self._unrefuted
                            and self.check(self.selected(parent), z3.Not(self.selected(name)))
                            is None
                        )
                    ):
                        found.append(name)
            self._false_optional = sorted(found)
        return self._false_optional

    def count(self, seconds: float | None = None) -> ProductCount:
        """The number of products (sets of selected features), one solver call each, or
        ``None`` past ``seconds``."""
        if not self.satisfiable():
            return ProductCount(0)
        if seconds is not None and seconds <= 0:
            return ProductCount(None, f"count skipped after {seconds:g} s")
        deadline = None if seconds is None else time.monotonic() + seconds
        features = [self.selected(name) for name in self.cnf.names]
        counted = 0
        self.solver.push()
        try:
            while (found := self.check()) is not None:
                counted += 1
                if deadline is not None and time.monotonic() > deadline:
                    return ProductCount(None, f"count skipped after {seconds:g} s")
                self.solver.add(
                    z3.Or([f != found.eval(f, model_completion=True) for f in features])
                )
        finally:
            self.solver.pop()
        return ProductCount(counted)


def _conditions(node: tuple) -> tuple[tuple, ...]:
    head = node[0]
    if head in ("ref", "cmp"):
        return ()
    return (node[1],) if head == "not" else (node[1], node[2])


def _terms(node: tuple) -> tuple[tuple, ...]:
    head = node[0]
    if head == "arith":
        return (node[2], node[3])
    if head in ("len", "floor", "ceil"):
        return (node[1],)
    if head in ("sum", "avg"):
        return tuple(value for _, value in node[1])
    return ()


def _post_order(
    root: tuple, parts: Callable[[tuple], tuple[tuple, ...]], build: Callable[[tuple, list], Any]
) -> Any:
    """``build(node, its operands built)`` from the leaves up, without recursion."""
    done: list[Any] = []
    work: list[tuple[tuple, bool]] = [(root, False)]
    while work:
        node, ready = work.pop()
        children = parts(node)
        if children and not ready:
            work.append((node, True))
            work.extend((child, False) for child in reversed(children))
            continue
        operands = done[len(done) - len(children) :] if children else []
        if children:
            del done[len(done) - len(children) :]
        done.append(build(node, operands))
    return done[0]
