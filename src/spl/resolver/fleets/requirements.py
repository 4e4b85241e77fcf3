"""The requirements a fleet puts on a robot's features, and their encoding for the SAT
solver (:mod:`spl.resolver.fleets.options` asks it which features the robot may still
choose). A requirement is a formula over activation literals, n-ary ``("or", parts)``,
``("and", parts)``, ``("not", f)``, ``("lit", v)`` and constants, Tseitin-encoded once
per distinct subformula behind a selector literal, so that an unsatisfiable query names
the requirements that caused it (a minimal core).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

from pysat.solvers import Solver

from spl.resolver.fleets.fleet import FleetCheck
from spl.resolver.resolution.effects import PLACEMENT, Aspect, Effect, NodeEffects, Settings

if TYPE_CHECKING:
    from spl.metamodels import rm_types, tsm_types
    from spl.resolver.resolution.effects import Value

TRUE, FALSE = ("const", True), ("const", False)


def any_of(parts: list) -> tuple:
    """The disjunction of ``parts``, folded where one is a constant."""
    parts = [p for p in parts if p != FALSE]
    if TRUE in parts:
        return TRUE
    return parts[0] if len(parts) == 1 else ("or", tuple(parts)) if parts else FALSE


def all_of(parts: list) -> tuple:
    """The conjunction of ``parts``, folded where one is a constant."""
    parts = [p for p in parts if p != TRUE]
    if FALSE in parts:
        return FALSE
    return parts[0] if len(parts) == 1 else ("and", tuple(parts)) if parts else TRUE


def negation(formula: tuple) -> tuple:
    if formula[0] == "const":
        return FALSE if formula[1] else TRUE
    return ("not", formula)


@dataclass(frozen=True)
class Requirement:
    text: str
    effects: tuple[tuple[Effect, Value], ...] = ()  # (effect, value) that break it
    fixed: Value = None  # the value that meets it


class RequirementEncoding:
    """The feature model plus requirements in one incremental solver (Tseitin)."""

    def __init__(self, check: FleetCheck, settings: Settings) -> None:
        self.cnf = check.line.formula.cnf
        self.effects = check.effects
        self.settings = settings
        self.solver = Solver(
            name=check.line.formula.solver_name, bootstrap_with=list(self.cnf.clauses)
        )
        self.top = self.cnf.num_vars
        self.cache: dict[tuple, int] = {}
        self.selectors: dict[int, Requirement] = {}
        self._exclude_conflicting_elements()

    def fresh(self) -> int:
        self.top += 1
        return self.top

    def literal(self, formula: tuple) -> int:
        kind = formula[0]
        if kind == "lit":
            return formula[1]
        if kind == "not":
            return -self.literal(formula[1])
        if formula in self.cache:
            return self.cache[formula]
        v = self.fresh()
        if kind == "const":
            self.solver.add_clause([v] if formula[1] else [-v])
        else:
            parts = [self.literal(p) for p in formula[1]]
            if kind == "and":
                self.solver.add_clause([v, *[-p for p in parts]])
                for p in parts:
                    self.solver.add_clause([-v, p])
            else:
                self.solver.add_clause([-v, *parts])
                for p in parts:
                    self.solver.add_clause([v, -p])
        self.cache[formula] = v
        return v

    def active(self, element: rm_types.ResolutionElement) -> tuple:
        v = self.cnf.var[element.feature.name]
        return ("lit", v if element.activeIfSelected else -v)

    def equals(self, aspect: Aspect, value: Value) -> tuple:
        """The aspect has ``value`` in the robot's product."""
        effects = aspect.effects
        parts = [self.active(e.element) for e in effects if e.value_for(self.settings) == value]
        if aspect.default == value:
            parts.append(all_of([negation(self.active(e.element)) for e in effects]))
        return any_of(parts)

    def present(self, node: NodeEffects) -> tuple:
        return TRUE if not node.node.optional else any_of([self.active(e) for e in node.keepers])

    def value_equals(self, node: NodeEffects, aspect: str, value: Value) -> tuple:
        if not aspect.startswith("server of "):
            return self.equals(node.aspects[aspect], value)
        chosen = node.servers[aspect.removeprefix("server of ")]
        wanted = cast("tuple[str, str] | None", value)  # (server id, placement), or none
        cases = []
        servers = [chosen.default, *(e.value for e in chosen.effects)]
        for server in {id(s): cast("tsm_types.ServiceServer | None", s) for s in servers}.values():
            picked = self.equals(chosen, server)
            server_node = self.effects.by_node.get(id(server.eContainer())) if server else None
            if wanted is None:
                gone = TRUE if server_node is None else negation(self.present(server_node))
                cases.append(all_of([picked, gone]))
            elif server_node is not None and wanted[0] == server_id(
                server_node, cast("tsm_types.ServiceServer", server)
            ):
                placed = self.equals(server_node.aspects[PLACEMENT], wanted[1])
                cases.append(all_of([picked, self.present(server_node), placed]))
        return any_of(cases)

    def require(self, requirement: Requirement, formula: tuple) -> None:
        selector = self.fresh()
        self.solver.add_clause([-selector, self.literal(formula)])
        self.selectors[selector] = requirement

    def _exclude_conflicting_elements(self) -> None:
        for node in self.effects.nodes.values():
            for aspect in [*node.aspects.values(), *node.servers.values()]:
                effects = aspect.effects
                for i, first in enumerate(effects):
                    for second in effects[i + 1 :]:
                        if first.value_for(self.settings) != second.value_for(self.settings):
                            a, b = self.active(first.element), self.active(second.element)
                            if a[1] != -b[1]:
                                self.solver.add_clause([-a[1], -b[1]])

    def core(self, assumptions: list[int]) -> list[int]:
        """A minimal set of selectors that, with ``assumptions``, has no product."""
        selectors = list(self.selectors)
        if self.solver.solve(assumptions=assumptions + selectors):
            return []
        core = [s for s in selectors if s in set(self.solver.get_core() or [])]
        for s in list(core):
            rest = [c for c in core if c != s]
            if not self.solver.solve(assumptions=assumptions + rest):
                found = set(self.solver.get_core() or [])
                core = [c for c in rest if c in found]
        return core


def server_id(server_node: NodeEffects, server: tsm_types.ServiceServer) -> str:
    return f"{server_node.origin}.{server_node.name}.{server.name}"
