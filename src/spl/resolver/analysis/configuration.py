"""Decision propagation for an interactive configurator (docs/configure.md, "Propagation").

A user decides features one at a time; after each decision every feature is in one of
five states: ``selected`` or ``deselected`` (decided), ``implied-selected`` or
``implied-deselected`` (the same value in *every* product containing the decisions: the
backbone under them, not only what unit propagation finds) or ``open``.

The backbone is computed on the feature model's one incremental solver
(:class:`~spl.resolver.analysis.formula.FeatureModelFormula`), with the decisions as
assumptions, exactly as :mod:`spl.resolver.analysis.operations.backbone` computes it without
them: one model gives the candidates, every further model drops the candidates it
disagrees with (the solver's preferred phases set against them so it disagrees with as
many as it can), unit propagation settles most survivors without search, and each other
survivor costs one call under the assumptions plus its negation. Two things make a
decision cheap on a large model: the models found are kept, so a later query first
drops the candidates any kept model consistent with its decisions refutes; and the
answer for a set of decisions is remembered, so undo and redo cost nothing and a new
decision starts from what its subset of decisions already implied (adding a decision
never makes an implied feature open).

Why a feature is implied is what :func:`~spl.resolver.resolution.selection.check_selection` says
about the decisions with that feature flipped: the minimal rules, with their
``file:line``, and the minimal decisions that contradict it (the wording of
``spl resolve`` and ``spl explain``).
"""

from __future__ import annotations

import sys
from array import array
from collections import OrderedDict
from collections.abc import Mapping
from dataclasses import dataclass

from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.resolution.selection import SelectionCheck, check_selection

OPEN = "open"
SELECTED = "selected"
DESELECTED = "deselected"
IMPLIED_SELECTED = "implied-selected"
IMPLIED_DESELECTED = "implied-deselected"
STATES = (OPEN, SELECTED, DESELECTED, IMPLIED_SELECTED, IMPLIED_DESELECTED)

# Kept models (each a list of n literals) and remembered answers: enough for a long
# session on automotive01 (2,513 features: ~10 KB per model) without growing unbounded.
KEPT_MODELS = 400
REMEMBERED = 256
# a model's sign bits: the high byte of each 32-bit literal is 0x00 (true) or 0xff (false)
_SIGN_DIGITS = bytes.maketrans(b"\x00\xff", b"10")


class Impossible(ValueError):
    """A decision that leaves no product; ``lines`` say why (rules and decisions)."""

    def __init__(self, lines: list[str]) -> None:
        super().__init__("; ".join(lines))
        self.lines = lines


@dataclass(frozen=True)
class Propagation:
    """Every feature's value fixed by the decisions (decided or implied), by variable."""

    fixed: Mapping[int, bool]
    models: tuple[int, ...]  # products seen that contain the decisions (bit v: variable v)


class Propagator:
    """The backbone of a feature model under changing decisions, on its one solver."""

    def __init__(self, formula: FeatureModelFormula) -> None:
        self.formula = formula
        self.cnf = formula.cnf
        self.n = formula.cnf.num_features
        core, dead = formula.backbone()  # adds them as units: every later query is shorter
        var = self.cnf.var
        self.base: dict[int, bool] = {var[name]: True for name in core}
        self.base.update({var[name]: False for name in dead})
        self.everything = (1 << (self.n + 1)) - 2  # bits 1..n
        self.models: list[int] = []
        for sample in formula.recent:
            self._keep(sample)
        self.remembered: OrderedDict[frozenset[int], Propagation] = OrderedDict()

    def propagate(self, decisions: Mapping[str, bool]) -> Propagation:
        """The features fixed by ``decisions`` (name -> value); :class:`Impossible` when
        no product contains them all."""
        var = self.cnf.var
        assumptions = [var[name] if value else -var[name] for name, value in decisions.items()]
        key = frozenset(assumptions)
        known = self.remembered.get(key)
        if known is not None:
            self.remembered.move_to_end(key)
            return known
        if not self.formula.satisfiable():
            raise Impossible(self.why_impossible(decisions))
        start = dict(self.base)
        for subset, answer in reversed(self.remembered.items()):  # latest first
            if subset <= key:  # what fewer decisions implied, these imply too
                start.update(answer.fixed)
                break
        fixed = self._backbone(assumptions, start)
        if fixed is None:
            raise Impossible(self.why_impossible(decisions))
        must, never = _masks(assumptions)
        consistent = tuple(m for m in self.models if m & must == must and not m & never)
        result = Propagation(fixed, consistent)
        self.remembered[key] = result
        if len(self.remembered) > REMEMBERED:
            self.remembered.popitem(last=False)
        return result

    def _backbone(self, assumptions: list[int], start: dict[int, bool]) -> dict[int, bool] | None:
        """The backbone under ``assumptions``. Models are bit masks (bit v set: feature
        variable v true) and so are the candidates (``up``: candidates true in every
        model so far, ``down``: false in every one), so dropping the candidates a model
        refutes is two integer operations, not a loop over 2,500 features."""
        solver = self.formula.solver
        n = self.n
        ok, propagated = solver.propagate(assumptions=assumptions)
        if not ok:
            return None
        fixed = dict(start)
        fixed.update({abs(lit): lit > 0 for lit in propagated if abs(lit) <= n})
        must, never = _masks(assumptions)
        consistent = [m for m in self.models if m & must == must and not m & never]
        if not consistent:
            if not solver.solve(assumptions=assumptions):
                return None
            consistent = [self._keep(solver.get_model())]
        undecided = self.everything & ~sum(1 << v for v in fixed)
        up, down = undecided, undecided
        for model in consistent:
            up &= model
            down &= ~model
        # the phases steer the solver against the candidates, set again after every model
        # (every fourth model instead costs more models than the calls it saves)
        phases_stale = True
        while up | down:
            both = up | down
            lowest = (both & -both).bit_length() - 1
            literal = lowest if up >> lowest & 1 else -lowest
            up &= ~(1 << lowest)
            down &= ~(1 << lowest)
            probe = [*assumptions, -literal]
            if not solver.propagate(assumptions=probe)[0]:
                implied = True
            else:
                if phases_stale:
                    solver.set_phases(_literals(down, True) + _literals(up, False))
                    phases_stale = False
                implied = not solver.solve(assumptions=probe)
            if implied:
                fixed[lowest] = literal > 0
            else:
                model = self._keep(solver.get_model())
                up &= model
                down &= ~model
                phases_stale = True
        return fixed

    def _keep(self, model: list[int]) -> int:
        mask = _mask(model, self.n)
        self.models.append(mask)
        if len(self.models) > KEPT_MODELS:
            del self.models[: len(self.models) - KEPT_MODELS]
        return mask

    def complete(self, propagation: Propagation) -> bool:
        """Whether the decided and implied features, every other feature left out, are a
        product: then the selection resolves (the ``complete`` of check_selection)."""
        closed = [v if propagation.fixed.get(v, False) else -v for v in range(1, self.n + 1)]
        return bool(self.formula.solver.solve(assumptions=closed))

    def why(self, decisions: Mapping[str, bool], feature: str, value: bool) -> list[str]:
        """Why ``feature`` has ``value`` in every product of ``decisions``: the rules and
        decisions that contradict the other value, in check_selection's words."""
        flipped = {name: v for name, v in decisions.items() if name != feature}
        flipped[feature] = not value
        check = self._check(flipped)
        if check.valid:  # a caller's mistake: the feature is not implied
            return [f"nothing forces {feature}"]
        others = {n: flipped[n] for n in check.conflicting if n != feature}
        verb = "deselecting" if value else "selecting"
        against = f"your decisions ({_decided(others)})" if others else "the feature model"
        return [f"{verb} {feature} contradicts {against}:"] + [
            f"  {rule}" for rule in check.conflict
        ]

    def why_impossible(self, decisions: Mapping[str, bool]) -> list[str]:
        """Why no product contains ``decisions``: the violated rules, minimal decisions
        (as ``spl resolve`` words an invalid selection)."""
        check = self._check(decisions)
        if check.valid:
            return ["the decisions have a product"]
        subject = _decided({n: decisions[n] for n in check.conflicting}) or "the feature model"
        return [f"{subject} contradicts:"] + [f"  {rule}" for rule in check.conflict]

    def _check(self, decisions: Mapping[str, bool]) -> SelectionCheck:
        selected = [name for name, value in decisions.items() if value]
        deselected = [name for name, value in decisions.items() if not value]
        return check_selection(self.formula, selected, deselected)

    def states(self, decisions: Mapping[str, bool], propagation: Propagation) -> dict[str, str]:
        """Every feature's state, in tree order."""
        names = self.cnf.names
        var = self.cnf.var
        result = {}
        for name in names:
            if name in decisions:
                result[name] = SELECTED if decisions[name] else DESELECTED
                continue
            value = propagation.fixed.get(var[name])
            if value is None:
                result[name] = OPEN
            else:
                result[name] = IMPLIED_SELECTED if value else IMPLIED_DESELECTED
        return result


def _mask(model: list[int], n: int) -> int:
    """The bit mask of a model's true feature variables (bit v: variable v), built by C
    code (array, translate, int) rather than a loop over 2,500 literals in Python."""
    high = array("i", model[:n]).tobytes()[3::4] if sys.byteorder == "little" else None
    if high is None:  # big-endian: the sign is in each literal's first byte
        high = array("i", model[:n]).tobytes()[0::4]
    return int(high.translate(_SIGN_DIGITS)[::-1] + b"0", 2)


def _masks(literals: list[int]) -> tuple[int, int]:
    """(true, false): the bit masks of the positive and of the negated variables."""
    true = false = 0
    for lit in literals:
        if lit > 0:
            true |= 1 << lit
        else:
            false |= 1 << -lit
    return true, false


def _literals(mask: int, value: bool) -> list[int]:
    """The variables of ``mask`` as literals of ``value``."""
    out = []
    while mask:
        low = mask & -mask
        v = low.bit_length() - 1
        out.append(v if value else -v)
        mask ^= low
    return out


def _decided(decisions: Mapping[str, bool]) -> str:
    """``selecting A, B and deselecting C``, as an invalid selection's message says it."""
    picked = [name for name, value in decisions.items() if value]
    dropped = [name for name, value in decisions.items() if not value]
    parts = []
    if picked:
        parts.append("selecting " + ", ".join(picked))
    if dropped:
        parts.append("deselecting " + ", ".join(dropped))
    return " and ".join(parts)
