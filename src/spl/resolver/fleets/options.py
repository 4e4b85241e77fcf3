"""Which features a robot may still choose, given the robots of its fleet as deployed.

The robots already in the fleet fix every shared node they use
(:mod:`spl.resolver.fleets.fleet`). For the robot to add (or change) this module asks the
SAT solver, never an enumeration of products: the feature model's clauses, plus one
*requirement* per fixed aspect of a shared node the robot would share, encoded over the
robot's features with the effects model (:mod:`spl.resolver.resolution.effects`, which
element sets which aspect to what):

    the robot shares node X with the robot that fixed it  (X present, shared, in scope;
    not both on board)  =>  X's <aspect> has the fixed value

where "X's aspect has value v" is "an element giving v is active, or none giving any
value is (and the template has v)". Requirements sit behind selector literals, so an
unsatisfiable query comes back with the requirements that caused it (a minimal core):
a feature is *forced* when the robot cannot join without it, *forbidden* when it cannot
join with it, *free* otherwise, each with its reason; when no product meets all
requirements the robot cannot join at all, and the blocking requirements are named. A
robot's capability file (``capabilities:``) adds its choices as requirements too.
Two active elements that decide one aspect differently are excluded as the engine
excludes them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Diagnostic, Location, ModelError
from spl.dsl.fm.language import all_features
from spl.resolver.architecture.flows import node_of
from spl.resolver.fleets.asks import SERVER_INSTANCE, Ask, shown
from spl.resolver.fleets.fleet import FleetCheck, check_fleet
from spl.resolver.fleets.fleet_file import DEFAULT_GROUP, Fleet
from spl.resolver.fleets.requirements import (
    FALSE,
    Requirement,
    RequirementEncoding,
    all_of,
    any_of,
    negation,
    server_id,
)
from spl.resolver.resolution.capabilities import choose_features
from spl.resolver.resolution.context import describe
from spl.resolver.resolution.effects import (
    PLACEMENT,
    SHARING,
    Effect,
    NodeEffects,
    Settings,
)

if TYPE_CHECKING:
    from spl.metamodels import fm_types, tsm_types
    from spl.resolver.architecture.product import AttributeValue
    from spl.resolver.resolution.effects import Value
    from spl.resolver.resolution.product_selection import ProductSelection


@dataclass(frozen=True)
class FeatureOption:
    feature: str
    status: str  # forced | forbidden | free
    reasons: tuple[str, ...] = ()


@dataclass
class FleetOptions:
    robot: str
    group: str
    fixed_by: tuple[str, ...]  # the robots whose instances this robot would share
    joinable: bool
    blocking: tuple[str, ...] = ()
    options: list[FeatureOption] = field(default_factory=list)
    core: tuple[str, ...] = ()  # in every product of the feature model
    dead: tuple[str, ...] = ()  # in none
    fleet_problems: tuple[Diagnostic, ...] = ()  # conflicts among the others
    alternatives: tuple[str, ...] = ()  # sharing overrides with which it could join


def _sharing_problems(fm: fm_types.FeatureModel, sharing: dict[str, str]) -> list[Diagnostic]:
    """``--sharing`` overrides of features that have no sharing mode to override (as a
    resolve refuses them; unchecked, a misspelt feature gave a confident answer)."""
    modes = {f.name: f.sharing is not None for f in all_features(fm)}
    where = Location("--sharing", 1, 1)
    return [
        Diagnostic(
            where,
            f"unknown feature {name}"
            if name not in modes
            else f"sharing given for {name}, which has no sharing attribute",
        )
        for name in sorted(sharing)
        if not modes.get(name)
    ]


def fleet_options(
    fleet: Fleet, name: str, group: str | None = None, sharing: dict[str, str] | None = None
) -> FleetOptions:
    """The options of robot ``name`` (in the fleet or to be added) in ``group``, with the
    sharing modes and attributes of its entry (``sharing`` overrides the modes)."""
    entry = fleet.robot(name)
    group = group or (entry.group if entry is not None else DEFAULT_GROUP)
    others = Fleet(
        fleet.name, fleet.source, fleet.product_line, [r for r in fleet.robots if r is not entry]
    )
    check = check_fleet(others)
    errors = [d for d in check.diagnostics if d.severity == "error" and d.code != "SPL040"]
    errors += _sharing_problems(check.line.fm, sharing or {})
    if errors:
        raise ModelError(errors)
    selection = entry.selection if entry is not None else None
    settings = Settings.of(
        {**(selection.sharing if selection else {}), **(sharing or {})},
        # the robot's attributes, checked as its product resolved
        cast("dict[str, AttributeValue]", selection.attributes) if selection else {},
    )
    encoding, fixed_by = _build(check, selection, group, settings)
    core, dead = check.line.formula.backbone()
    result = FleetOptions(
        name,
        group,
        tuple(fixed_by),
        True,
        core=tuple(n for n in encoding.cnf.names if n in core),
        dead=tuple(n for n in encoding.cnf.names if n in dead),
        fleet_problems=tuple(d for d in check.diagnostics if d.code == "SPL040"),
    )
    blocking = encoding.core([])
    if blocking:
        encoding.solver.delete()
        result.joinable = False
        result.blocking = tuple(encoding.selectors[s].text for s in blocking)
        result.alternatives = _sharing_alternatives(check, selection, group, settings)
        return result
    for feature in encoding.cnf.names:
        if feature in core or feature in dead:
            continue
        v = encoding.cnf.var[feature]
        if encoding.core([v]):
            result.options.append(_explained(encoding, feature, "forbidden", v))
        elif encoding.core([-v]):
            result.options.append(_explained(encoding, feature, "forced", -v))
        else:
            result.options.append(FeatureOption(feature, "free"))
    encoding.solver.delete()
    return result


def _build(
    check: FleetCheck, selection: ProductSelection | None, group: str, settings: Settings
) -> tuple[RequirementEncoding, list[str]]:
    """The encoding with every requirement: shared nodes, and the robot's capabilities."""
    encoding = RequirementEncoding(check, settings)
    fixed_by = _requirements(encoding, check.asks, group)
    if selection is not None and selection.capabilities is not None:
        for choice in choose_features(check.line.fm, selection.capabilities):
            v = encoding.cnf.var[choice.feature]
            encoding.require(Requirement(str(choice)), ("lit", v if choice.selected else -v))
    return encoding, fixed_by


def _sharing_alternatives(
    check: FleetCheck, selection: ProductSelection | None, group: str, settings: Settings
) -> tuple[str, ...]:
    """The sharing overrides (one feature, one mode) with which the robot could join."""
    found = []
    for feature in all_features(check.line.fm):
        if feature.sharing is None:
            continue
        for mode in ("private", "protected", "public"):
            if dict(settings.sharing).get(feature.name, feature.sharing.mode.name) == mode:
                continue
            changed = Settings(
                tuple(sorted({**dict(settings.sharing), feature.name: mode}.items())),
                settings.attributes,
            )
            encoding = _build(check, selection, group, changed)[0]
            if not encoding.core([]):
                found.append(f"{feature.name}: {mode}")
            encoding.solver.delete()
    return tuple(found)


def _requirements(encoding: RequirementEncoding, asks: list[Ask], group: str) -> list[str]:
    """One requirement per fixed aspect of every shared node the robot could share."""
    seen: set[tuple] = set()
    robots: list[str] = []
    for ask in asks:
        scope = "group" if ask.group == group else "public" if ask.mode == "public" else None
        identity = (scope, ask.key, ask.mode, ask.placement, ask.on_robot, ask.values)
        if scope is None or identity in seen:
            continue
        seen.add(identity)
        robots.append(ask.robot)
        node = encoding.effects.nodes[ask.key]
        shared_mode = (
            any_of([encoding.equals(node.aspects[SHARING], m) for m in ("protected", "public")])
            if scope == "group"
            else encoding.equals(node.aspects[SHARING], "public")
        )
        comparable = all_of([encoding.present(node), shared_mode])
        robot_containers = sorted(encoding.effects.robot_containers)
        on_board = any_of([encoding.equals(node.aspects[PLACEMENT], r) for r in robot_containers])
        exempt = any_of([negation(comparable), on_board if ask.on_robot else FALSE])
        suffix = f", as {ask.robot} fixed it ({ask.where()})"
        wanted: list[tuple[str, Value]] = [
            (PLACEMENT, ask.placement),
            (SHARING, ask.mode),
        ]
        if not ask.on_robot:  # a server's instance is a warning of the check, not a rule
            wanted += [(a, v) for a, v in ask.values if not a.startswith(SERVER_INSTANCE)]
        for aspect, value in wanted:
            if aspect == PLACEMENT:
                where = "on the robot" if ask.on_robot else f"in {ask.placement}"
                text = f"{ask.node} must run {where}{suffix}"
            elif aspect == SHARING:
                text = f"{ask.node} must be shared {ask.mode}{suffix}"
            else:
                text = f"{ask.node} must have {aspect} {shown(ask, aspect)}{suffix}"
            breaking = _breaking(encoding, node, aspect, value)
            encoding.require(
                Requirement(text, breaking, value),
                any_of([exempt, encoding.value_equals(node, aspect, value)]),
            )
    return list(dict.fromkeys(robots))


def _breaking(
    encoding: RequirementEncoding, node: NodeEffects, aspect: str, value: Value
) -> tuple[tuple[Effect, Value], ...]:
    """The effects that would give the aspect another value than ``value``."""
    if aspect.startswith("server of "):
        chosen = node.servers[aspect.removeprefix("server of ")]
        found: list[tuple[Effect, Value]] = []
        server_wanted = cast("tuple[str, str] | None", value)  # (server id, placement)
        for effect in chosen.effects:
            server = cast("tsm_types.ServiceServer", effect.value)  # a statement's server
            server_node = encoding.effects.by_node.get(id(server.eContainer()))
            given = server_id(server_node, server) if server_node else None
            if server_wanted is None or given != server_wanted[0]:
                found.append((effect, f"{node_of(server).name}.{server.name}"))
        return tuple(found)
    values = [(e, e.value_for(encoding.settings)) for e in node.aspects[aspect].effects]
    return tuple((e, v) for e, v in values if v != value)


def _explained(
    encoding: RequirementEncoding, feature: str, status: str, literal: int
) -> FeatureOption:
    """A forced or forbidden feature with the requirements that make it so, and the
    resolution elements through which the feature would break them."""
    reasons = []
    for selector in encoding.core([literal]):
        requirement = encoding.selectors[selector]
        text = requirement.text
        if status == "forbidden":
            through = [
                f"{feature} makes it {_value_text(given)} ({describe(effect.element)})"
                for effect, given in requirement.effects
                if not encoding.solver.solve(
                    assumptions=[literal, -encoding.literal(encoding.active(effect.element))]
                )
            ]
            if through:
                text += "; " + "; ".join(through)
        reasons.append(text)
    return FeatureOption(feature, status, tuple(reasons))


def _value_text(value: Value) -> str:
    return "none" if value is None else str(value)
