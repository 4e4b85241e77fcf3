"""What every session of one ``spl configure`` shares: the models read once, the feature
tree as the page lists it, one solver (behind a lock: sessions decide in threads) and,
in fleet mode, the decisions the fleet's shared instances fix (docs/configure.md).

A product-line folder gives the whole configurator (attributes, sharing, deployment,
the architecture and its bundle); a bare feature model (.fm, .uvl, FeatureIDE .xml)
gives the analysis only, as ``spl products`` reads it.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from spl.core.diagnostics import Diagnostic, ModelError
from spl.resolver.analysis.configuration import Propagator
from spl.resolver.analysis.fm_rules import group_bounds, group_kind
from spl.resolver.analysis.formula import FeatureModelFormula

if TYPE_CHECKING:
    from spl.resolver.resolution.product_line import ProductLine
    from spl.resolver.resolution.product_selection import ProductSelection

FEATURE_MODEL_SUFFIXES = (".fm", ".uvl", ".xml")


@dataclass(frozen=True)
class AttributeInfo:
    name: str
    kind: str  # int | double | string | bool
    default: str


@dataclass(frozen=True)
class FeatureRow:
    """One feature as the page lists it: depth in the tree and how its parent holds it."""

    name: str
    depth: int
    parent: str | None
    relation: str  # root | mandatory | optional | alternative | or | [l..u]
    group: str  # the parent's group as words ("" for the root)
    attributes: tuple[AttributeInfo, ...] = ()
    sharing: str | None = None  # the feature model's default sharing mode


@dataclass
class Workspace:
    source: Path
    formula: FeatureModelFormula
    rows: list[FeatureRow]
    line: ProductLine | None = None
    locks: dict[str, bool] = field(default_factory=dict)  # fleet: feature -> value
    lock_reasons: dict[str, list[str]] = field(default_factory=dict)
    fleet_label: str = ""
    robot: str | None = None
    robot_containers: tuple[str, ...] = ()
    initial: ProductSelection | None = None  # fleet mode: the robot's entry, if it has one
    guard: threading.Lock = field(default_factory=threading.Lock)

    def __post_init__(self) -> None:
        self.propagator = Propagator(self.formula)
        self.by_name = {row.name: row for row in self.rows}

    @property
    def title(self) -> str:
        return self.line.name if self.line is not None else self.source.name

    @property
    def analysis_only(self) -> bool:
        return self.line is None


def load_workspace(source: Path) -> Workspace:
    """A product-line folder or a feature-model file; ModelError or ValueError if neither."""
    if source.is_dir():
        from spl.resolver.resolution.product_line import load_product_line

        line = load_product_line(source)
        containers = tuple(c.name for c in line.tsm.containers if c.eClass.name == "RobotContainer")
        return Workspace(
            source, line.formula, feature_rows(line.fm), line, robot_containers=containers
        )
    if source.suffix.lower() not in FEATURE_MODEL_SUFFIXES:
        raise ValueError(
            f"{source}: expected a product-line folder or a .fm, .uvl or .xml feature model"
        )
    from spl.dsl.interop.formats import load_analysable_model

    model = load_analysable_model(source)
    return Workspace(source, FeatureModelFormula(model), feature_rows(model))


def load_fleet_workspace(fleet_file: Path, robot: str, group: str | None) -> Workspace:
    """The fleet's product line, with the features the fleet forces or forbids for
    ``robot`` locked, each with the reason ``spl fleet options`` gives."""
    from spl.resolver.fleets.fleet_file import load_fleet
    from spl.resolver.fleets.options import fleet_options

    fleet = load_fleet(fleet_file)
    options = fleet_options(fleet, robot, group)
    if not options.joinable:
        message = f"robot {robot} cannot join group {options.group}: " + "; ".join(options.blocking)
        raise ModelError([Diagnostic(None, message)])
    workspace = load_workspace(fleet.product_line)
    for option in options.options:
        if option.status in ("forced", "forbidden"):
            workspace.locks[option.feature] = option.status == "forced"
            workspace.lock_reasons[option.feature] = [
                f"the fleet {'forces' if option.status == 'forced' else 'forbids'} it: {reason}"
                for reason in option.reasons
            ]
    workspace.fleet_label = f"robot {robot} joining fleet {fleet.name}, group {options.group}"
    workspace.robot = robot
    entry = fleet.robot(robot)
    workspace.initial = entry.selection if entry is not None else None
    return workspace


def feature_rows(model: Any) -> list[FeatureRow]:
    """The tree in pre-order (the CNF's variable order), read from an ecore or a plain
    feature model alike."""
    rows: list[FeatureRow] = []
    stack: list[tuple[Any, int, str | None, str, str]] = [(model.root, 0, None, "root", "")]
    while stack:
        feature, depth, parent, relation, group_text = stack.pop()
        attributes = tuple(
            AttributeInfo(a.name, getattr(a.type, "name", a.type), str(a.value))
            for a in getattr(feature, "attributes", ())
        )
        sharing = getattr(feature, "sharing", None)
        mode = getattr(getattr(sharing, "mode", None), "name", None) if sharing else None
        rows.append(FeatureRow(feature.name, depth, parent, relation, group_text, attributes, mode))
        pushed = []
        for group in feature.groups:
            kind = group_kind(group)
            members = list(group.features)
            if kind in ("mandatory", "optional"):
                relation_text, words = kind, ""
            elif kind in ("alternative", "or"):
                relation_text = kind
                words = "exactly one of" if kind == "alternative" else "at least one of"
            else:
                lower, upper = group_bounds(group, kind, len(members))
                relation_text = f"[{lower}..{'*' if upper < 0 else upper}]"
                words = f"between {lower} and {'any' if upper < 0 else upper} of"
            for child in members:
                pushed.append((child, depth + 1, feature.name, relation_text, words))
        stack.extend(reversed(pushed))
    return rows
