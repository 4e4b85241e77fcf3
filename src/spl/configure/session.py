"""One browser session's configuration: its decisions, the attribute values, sharing
modes and deployment values it set, a robot capability file it imported, and its undo
and redo history (docs/configure.md). Sessions share the workspace's solver, never
their state: two browsers configure independently.

Everything a session holds is what a ``products/*.yaml`` selection can say
(docs/resolution.md, "Selections"), checked with the same rules as that file's reader,
so the selection it exports resolves as ``spl resolve --features FILE.yaml`` resolves it.
"""

from __future__ import annotations

import copy
import math
import re
import threading
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from spl.resolver.analysis.configuration import Impossible, Propagation
from spl.resolver.analysis.operations.product_count import count_with_fixed
from spl.resolver.resolution.product_selection import (
    DEPLOYMENT_KEYS,
    IDENT,
    SHARING_MODES,
    ProductSelection,
    typed_text,
)

if TYPE_CHECKING:
    from spl.configure.workspace import Workspace
    from spl.resolver.resolution.capabilities import RobotCapabilities

# The remaining count answered with a decision is given this long (a decision must be
# answered within 50 ms on a 2,500-feature model, docs/configure.md "Speed"); past it
# the page shows a lower bound, asks again with FOLLOW_UP_SECONDS, and offers a button
# that counts with COUNT_SECONDS.
QUICK_COUNT_SECONDS = 0.005
FOLLOW_UP_SECONDS = 0.25
COUNT_SECONDS = 10.0


class InputError(ValueError):
    """A value the user typed that the selection cannot hold (shown next to the field)."""


@dataclass
class Choices:
    """What the user decided: the part of a session undo and redo step through."""

    decisions: dict[str, bool] = field(default_factory=dict)
    attributes: dict[str, str] = field(default_factory=dict)  # "F.attr" -> text as typed
    sharing: dict[str, str] = field(default_factory=dict)
    deployment: dict[str, dict[str, str]] = field(default_factory=dict)
    capabilities: dict[str, bool] = field(default_factory=dict)  # chosen by the robot file
    capability_reasons: dict[str, str] = field(default_factory=dict)
    capability_file: str = ""


@dataclass
class Session:
    workspace: Workspace
    choices: Choices = field(default_factory=Choices)
    undo_stack: list[Choices] = field(default_factory=list)
    redo_stack: list[Choices] = field(default_factory=list)
    shown: dict[str, str] = field(default_factory=dict)  # states the page was last sent
    derived: dict[str, object] = field(default_factory=dict)  # selection key -> derivation
    lock: threading.Lock = field(default_factory=threading.Lock)

    # --- decisions --------------------------------------------------------------------
    def assumptions(self, choices: Choices | None = None) -> dict[str, bool]:
        """Every fixed value: the fleet's, the robot capability file's, the user's."""
        choices = choices or self.choices
        return {**self.workspace.locks, **choices.capabilities, **choices.decisions}

    def propagation(self) -> Propagation:
        workspace = self.workspace
        with workspace.guard:
            return workspace.propagator.propagate(self.assumptions())

    def decide(self, feature: str, action: str) -> None:
        """``select``, ``deselect`` or ``clear`` a feature; :class:`Impossible` (nothing
        changed) when no product would be left, InputError for a name or action the
        model does not have, or a feature the fleet or the robot decides."""
        workspace = self.workspace
        if feature not in workspace.by_name:
            raise InputError(f"unknown feature {feature!r}")
        if action not in ("select", "deselect", "clear"):
            raise InputError(f"unknown action {action!r} (select, deselect, clear)")
        fixed_by = self.fixed_by(feature)
        if fixed_by:
            raise InputError(f"{feature} is decided by {fixed_by}: {self.lock_text(feature)}")
        after = copy.deepcopy(self.choices)
        after.decisions.pop(feature, None)
        if action != "clear":
            after.decisions[feature] = action == "select"
        with workspace.guard:
            workspace.propagator.propagate(self.assumptions(after))  # Impossible: unchanged
        self._change(after)

    def fixed_by(self, feature: str) -> str:
        if feature in self.workspace.locks:
            return "the fleet"
        if feature in self.choices.capabilities:
            return "the robot's capabilities"
        return ""

    def lock_text(self, feature: str) -> str:
        if feature in self.workspace.locks:
            return "; ".join(self.workspace.lock_reasons.get(feature, []))
        return self.choices.capability_reasons.get(feature, "")

    def explanation(self, feature: str) -> list[str]:
        """Why ``feature`` is in its state, in the words of ``spl explain`` and of an
        invalid selection's message (rules with ``file:line``, decisions)."""
        if feature not in self.workspace.by_name:
            raise InputError(f"unknown feature {feature!r}")
        decisions = self.assumptions()
        propagation = self.propagation()
        state = self.workspace.propagator.states(self.choices.decisions, propagation)[feature]
        selected = state in ("selected", "implied-selected")
        head = f"{feature}: {'selected feature' if selected else 'feature not selected'}"
        if feature in self.choices.decisions:
            return [head, f"  {'selected' if selected else 'deselected'} by you"]
        if self.fixed_by(feature):
            return [head, f"  {self.lock_text(feature)}"]
        if state == "open":
            return [f"{feature}: open; products with it and products without it remain"]
        propagator = self.workspace.propagator
        variable = self.workspace.formula.cnf.var[feature]
        # a core or dead feature is so in every product: the model alone says why, even
        # when the solver could also blame a decision
        given = {} if variable in propagator.base else decisions
        with self.workspace.guard:
            lines = propagator.why(given, feature, selected)
        named = set(re.findall(r"[A-Za-z_]\w*", lines[0]))
        for name in given:  # a decision the fleet or the robot made: its own reason
            if name != feature and name in named and self.fixed_by(name):
                lines.append(f"  {name}: {self.lock_text(name)}")
        return [head, *(f"  {line}" for line in lines)]

    # --- values -------------------------------------------------------------------------
    def set_attribute(self, key: str, text: str) -> None:
        """Set ``F.attr`` from the text typed, read by the attribute's type; empty text
        goes back to the default. InputError (nothing changed) when it does not fit."""
        feature, _, name = key.partition(".")
        row = self.workspace.by_name.get(feature)
        info = next((a for a in row.attributes if a.name == name), None) if row else None
        if info is None:
            raise InputError(f"unknown feature attribute {key}")
        after = copy.deepcopy(self.choices)
        if text.strip() == "":
            after.attributes.pop(key, None)
        else:
            value = typed_text(text.strip(), info.kind)
            if value is None or (isinstance(value, float) and not math.isfinite(value)):
                raise InputError(f"attribute {key} is {info.kind}, got {text!r}")
            after.attributes[key] = text.strip()
        self._change(after)

    def set_sharing(self, feature: str, mode: str) -> None:
        row = self.workspace.by_name.get(feature)
        if row is None or row.sharing is None:
            raise InputError(f"{feature} has no sharing mode to override")
        after = copy.deepcopy(self.choices)
        if mode == "" or mode == row.sharing:
            after.sharing.pop(feature, None)
        elif mode not in SHARING_MODES:
            raise InputError(f"sharing: expected one of {', '.join(SHARING_MODES)}")
        else:
            after.sharing[feature] = mode
        self._change(after)

    def set_deployment(self, container: str, key: str, value: str) -> None:
        if container not in self.workspace.robot_containers:
            raise InputError(f"deployment: {container!r} is not a robot container")
        pattern = DEPLOYMENT_KEYS.get(key)
        if pattern is None:
            raise InputError(f"deployment: unknown setting {key!r} (robot_id, url)")
        value = value.strip()
        if value and not pattern.fullmatch(value):
            raise InputError(f"deployment: {key} {value!r} is not valid")
        after = copy.deepcopy(self.choices)
        settings = after.deployment.setdefault(container, {})
        if value:
            settings[key] = value
        else:
            settings.pop(key, None)
        if not settings:
            after.deployment.pop(container)
        self._change(after)

    def use_capabilities(self, capabilities: RobotCapabilities) -> None:
        """The robot capability file's choices become fixed decisions (as ``spl resolve
        --capabilities``); a choice against the user's own decision is refused."""
        from spl.resolver.resolution.capabilities import choose_features

        line = self.workspace.line
        if line is None:
            raise InputError("a bare feature model has no robot capabilities")
        choices = choose_features(line.fm, capabilities)
        after = copy.deepcopy(self.choices)
        clashes = [
            f"{c.feature} is {'deselected' if c.selected else 'selected'} by you, but {c}"
            for c in choices
            if after.decisions.get(c.feature, c.selected) != c.selected
        ]
        if clashes:
            raise InputError("; ".join(clashes))
        after.capabilities = {c.feature: c.selected for c in choices}
        after.capability_reasons = {c.feature: str(c) for c in choices}
        after.capability_file = capabilities.name
        with self.workspace.guard:
            self.workspace.propagator.propagate(self.assumptions(after))
        self._change(after)

    def start_from(self, selection: ProductSelection) -> None:
        """Begin with a fleet entry's selection (the robot being changed), as if
        imported, without an undo step; a selection the fleet's locks now refuse is
        not taken (the page starts empty)."""
        from spl.resolver.resolution.capabilities import choose_features

        line = self.workspace.line
        after = Choices()
        if selection.capabilities is not None and line is not None:
            chosen = choose_features(line.fm, selection.capabilities)
            after.capabilities = {c.feature: c.selected for c in chosen}
            after.capability_reasons = {c.feature: str(c) for c in chosen}
            after.capability_file = selection.capabilities.name
        fixed = {**self.workspace.locks, **after.capabilities}
        wanted = {**dict.fromkeys(selection.features, True),
                  **dict.fromkeys(selection.deselected, False)}  # fmt: skip
        after.decisions = {n: v for n, v in wanted.items() if n not in fixed}
        after.sharing = dict(selection.sharing)
        after.deployment = copy.deepcopy(selection.deployment)
        after.attributes = {
            key: ("true" if v is True else "false" if v is False else str(v))
            for key, v in selection.attributes.items()
        }
        try:
            with self.workspace.guard:
                self.workspace.propagator.propagate(self.assumptions(after))
        except Impossible:
            return
        self.choices = after

    def replace(self, after: Choices) -> None:
        """Take an imported selection whole (checked by the caller), undoably."""
        with self.workspace.guard:
            self.workspace.propagator.propagate(self.assumptions(after))
        self._change(after)

    # --- history ------------------------------------------------------------------------
    def _change(self, after: Choices) -> None:
        self.undo_stack.append(self.choices)
        self.redo_stack.clear()
        self.choices = after

    def undo(self) -> None:
        if not self.undo_stack:
            raise InputError("nothing to undo")
        self.redo_stack.append(self.choices)
        self.choices = self.undo_stack.pop()

    def redo(self) -> None:
        if not self.redo_stack:
            raise InputError("nothing to redo")
        self.undo_stack.append(self.choices)
        self.choices = self.redo_stack.pop()

    # --- what the page shows ------------------------------------------------------------
    def view(self, full: bool, count_seconds: float = QUICK_COUNT_SECONDS) -> dict:
        """The page's data: the states (all, or those changed since the last view), the
        remaining count, whether the selection is complete, the values set."""
        workspace = self.workspace
        decisions = self.assumptions()
        with workspace.guard:
            propagation = workspace.propagator.propagate(decisions)
            states = workspace.propagator.states(self.choices.decisions, propagation)
            complete = workspace.propagator.complete(propagation)
        changed = {n: s for n, s in states.items() if full or self.shown.get(n) != s}
        self.shown = states
        return {
            "states": changed,
            "products": self.count(propagation, count_seconds),
            "complete": complete,
            "decisions": [
                {"feature": name, "value": value} for name, value in self.choices.decisions.items()
            ],
            "fixed": sorted(n for n in decisions if n not in self.choices.decisions),
            "attributes": dict(self.choices.attributes),
            "sharing": dict(self.choices.sharing),
            "deployment": copy.deepcopy(self.choices.deployment),
            "capabilities": self.choices.capability_file,
            "undo": bool(self.undo_stack),
            "redo": bool(self.redo_stack),
        }

    def complete(self) -> bool:
        """Whether the choices resolve: nothing left open that a product needs decided."""
        propagation = self.propagation()
        with self.workspace.guard:
            return self.workspace.propagator.complete(propagation)

    def count(self, propagation: Propagation, seconds: float) -> dict:
        """The exact count when it is found within ``seconds``, else a lower bound: the
        distinct products the solver met that contain the decisions."""
        counted = count_with_fixed(self.workspace.formula, propagation.fixed, seconds)
        if counted.value is not None:
            value = counted.value
            text = f"{value} product{'' if value == 1 else 's'}"
            if value >= 10**15:  # the exact digits stay in "value" (a string: JSON numbers
                text = f"{value:.3e} products ({len(str(value))} digits)"  # lose them)
            return {"exact": True, "value": str(value), "text": text}
        seen = len(set(propagation.models))
        return {
            "exact": False,
            "value": str(seen),
            "text": f"at least {seen} products (exact count not found within {seconds:g} s)",
        }

    # --- the selection ------------------------------------------------------------------
    def selection(self, name: str | None = None) -> ProductSelection:
        """The selection file's content: the user's decisions (the completion adds what
        they imply), the robot's choices, and the values of selected features only."""
        choices = self.choices
        decided = {**self.workspace.locks, **choices.capabilities, **choices.decisions}
        features = [n for n, v in decided.items() if v]
        deselected = [n for n, v in decided.items() if not v]
        propagation = self.propagation()
        var = self.workspace.formula.cnf.var
        chosen = {n for n in var if propagation.fixed.get(var[n])}
        attributes: dict[str, object] = {}
        for key, text in sorted(choices.attributes.items()):
            feature, _, attr = key.partition(".")
            if feature in chosen:
                kind = next(a.kind for a in self.workspace.by_name[feature].attributes
                            if a.name == attr)  # fmt: skip
                attributes[key] = typed_text(text, kind)
        default = self.workspace.robot or "_".join(features) or "configured"
        product = name or (default if IDENT.fullmatch(default) else "configured")
        return ProductSelection(
            name=product,
            features=features,
            deselected=deselected,
            sharing={f: m for f, m in sorted(choices.sharing.items()) if f in chosen},
            attributes=attributes,
            deployment=copy.deepcopy(choices.deployment),
        )


def valid_name(name: str) -> bool:
    """A selection saved into the line is ``products/NAME.yaml``: NAME an identifier."""
    return bool(re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,63}", name))


__all__ = ["Choices", "Impossible", "InputError", "Session", "valid_name"]
