"""The RoboEarth Cloud Engine's own acceptance rules, checked on a set of rce-ros files.

A JSON Schema says what one file may look like; it cannot say what the engine refuses
when the file is applied: an ``...Interface`` type on a robot, a connection between two
publishers, two message classes on one connection, a tag that names nothing. Those rules
span files, because a connection may name an interface that another robot of the same
user declares in its own file (the engine's ``lo_client.cfg`` connects to
``lo_server.cfg``'s interfaces); so a product's files are checked together.

Each container, node, parameter, interface and connection may be declared once per user
in the whole set: the engine creates it when the first file naming it is applied and
refuses a tag its user already has (rce-core's ``view_createContainer``) or a pair
already connected. So a shared container of a group is declared by one robot's file, and
the other robots' files of that user connect to its interfaces; a file connects only to
interfaces of its own user (``userID``).

Every problem names the file and the JSON path of the offending entry, e.g.
``Robot.json: connections[2]: ...``.
"""

from __future__ import annotations

import json
from collections import OrderedDict
from collections.abc import Callable, Hashable, Sequence
from typing import cast

from spl.generators.json_text import Document
from spl.generators.rapyuta.schema import ConfigurationProblem, schema_problems
from spl.metamodels.interface_kinds import FAMILIES, KINDS, side

# The engine's interface roles are the Rapyuta roles of spl's interface kinds
# (docs/architecture.md, "Interface kinds"): one per kind, the two of a family connectable
# (an action has none: its bridge is the topics it is made of, Family.ros1_topics).
ROLES = tuple(kind.rapyuta_role for kind in KINDS if kind.rapyuta_role is not None)
CONTAINER_SUFFIXES = ("Interface",)
ROBOT_SUFFIXES = ("Converter", "Forwarder")
# Pairs the engine connects (either order), whatever the suffix of each side: the two
# sides of one family, the side a flow starts at first (as the engine's refusal says them).
PAIRS = tuple(
    (
        side(family, family.flows_from_provider).rapyuta_role,
        side(family, not family.flows_from_provider).rapyuta_role,
    )
    for family in FAMILIES
    if not family.ros1_topics
)
CONNECTABLE = {frozenset(pair) for pair in PAIRS}


def check_all(
    configs: Sequence[object], names: Sequence[str], clean: CleanSets | None = None
) -> list[ConfigurationProblem]:
    """Schema and engine rules together: what a product's file set must pass; a set
    ``clean`` already holds is not checked again, and one found clean is added to it."""
    key = _content_key(configs, names) if clean is not None else None
    if clean is not None and key is not None and clean.holds(key):
        return []
    problems: list[ConfigurationProblem] = []
    for config, name in zip(configs, names, strict=True):
        problems.extend(schema_problems(config, name))
    problems += check_configurations(configs, names)
    if not problems and clean is not None and key is not None:
        clean.add(key)
    return problems


CLEAN_SETS = 512


class CleanSets:
    """File sets found clean, by content, kept by whoever checks many (a bundle's
    generation and its validation, a run of ``spl validate`` over a line's products, which
    share many robots' files) and passed to :func:`check_all`. The check is a function of
    the content alone, and that a set passes does not depend on the order of any object's
    keys, so a set equal to one found clean is clean. Only clean sets are kept (problems
    are reported in full, in the order of the keys they name); past ``limit`` the oldest
    go first."""

    def __init__(self, limit: int = CLEAN_SETS) -> None:
        self.limit = limit
        self.keys: OrderedDict[str, None] = OrderedDict()

    def holds(self, key: str) -> bool:
        if key in self.keys:
            self.keys.move_to_end(key)
            return True
        return False

    def add(self, key: str) -> None:
        self.keys[key] = None
        if len(self.keys) > self.limit:
            self.keys.popitem(last=False)


_JSON_SCALARS = (str, int, float, bool, type(None))


def _content_key(configs: Sequence[object], names: Sequence[str]) -> str | None:
    """The file set as canonical JSON (keys sorted), or None when it holds anything but
    JSON's own types (a tuple, a subclass, a key that is not a string), whose encoding
    would stand for another value: ``(1,)`` and ``[1]``, ``{1: x}`` and ``{"1": x}``."""
    pending: list[object] = [list(configs)]
    while pending:
        value = pending.pop()
        kind = type(value)
        if kind is dict:
            mapping = cast("dict[object, object]", value)
            if any(type(key) is not str for key in mapping):
                return None
            pending.extend(mapping.values())
        elif kind is list:
            pending.extend(cast("list[object]", value))
        elif kind not in _JSON_SCALARS:
            return None
    try:
        return json.dumps([list(names), list(configs)], sort_keys=True)
    except (TypeError, ValueError):  # a name that is no string
        return None


def _entries(config: object, key: str) -> list[tuple[int, Document]]:
    """The well-formed entries of one list; malformed ones are the schema's to report."""
    items = config.get(key) if isinstance(config, dict) else None
    if not isinstance(items, list):
        return []
    return [(index, item) for index, item in enumerate(items) if isinstance(item, dict)]


def _role_and_suffix(i_type: object) -> tuple[str, str] | None:
    if not isinstance(i_type, str):
        return None
    for role in ROLES:
        suffix = i_type[len(role) :]
        if i_type.startswith(role) and suffix in CONTAINER_SUFFIXES + ROBOT_SUFFIXES:
            return role, suffix
    return None


class _Declarations:
    """Declarations keyed by identity across the file set: each may be made once."""

    def __init__(self, kind: str, report: Callable[[str, str, str, str], None]) -> None:
        self.kind = kind
        self.report = report
        self.first: dict[Hashable, tuple[str, str, Document]] = {}  # (file, path, entry)

    def declare(self, key: Hashable, file: str, path: str, value: Document, label: str) -> None:
        known = self.first.get(key)
        if known is None:
            self.first[key] = (file, path, value)
            return
        known_file, known_path, known_value = known
        if known_file == file:
            self.report(
                file,
                path,
                f"{label} is declared twice in this file (first at {known_path})",
                f"duplicate-{self.kind}",
            )
        elif known_value != value:
            self.report(
                file,
                path,
                f"{label} is declared differently in {known_file} ({known_path}): applying "
                "both files would give it two definitions",
                f"conflicting-{self.kind}",
            )
        else:
            self.report(
                file,
                path,
                f"{label} is declared again, as in {known_file} ({known_path}): the engine "
                "refuses from the later file what its user already has; declare it in one "
                "file and connect to it from the others",
                f"redeclared-{self.kind}",
            )

    def __contains__(self, key: object) -> bool:
        return key in self.first

    def get(self, key: Hashable) -> Document | None:
        known = self.first.get(key)
        return known[2] if known else None


def check_configurations(
    configs: Sequence[object], names: Sequence[str]
) -> list[ConfigurationProblem]:
    """The engine's rules over a set of files applied together (one user's robots).

    Returns every problem found (empty when the engine would accept the whole set), in a
    stable order: by file, then JSON path.
    """
    problems: list[ConfigurationProblem] = []

    def report(file: str, path: str, message: str, rule: str) -> None:
        problems.append(ConfigurationProblem(file, path, message, rule))

    files_ = list(zip(names, configs, strict=True))
    robots: dict[str, str] = {}
    for name, config in files_:
        robot: object = config.get("robotID") if isinstance(config, dict) else None
        if not isinstance(robot, str):
            continue
        if robot in robots:
            report(
                name,
                "robotID",
                f"robot {robot!r} is also the robot of {robots[robot]}",
                "duplicate-robot",
            )
        else:
            robots[robot] = name

    # the engine keeps each user's containers, interfaces and connections apart
    user = {
        name: config.get("userID") if isinstance(config, dict) else None for name, config in files_
    }
    containers = _Declarations("container", report)
    for name, config in files_:
        for index, entry in _entries(config, "containers"):
            c_tag = entry.get("cTag")
            path = f"containers[{index}]"
            if c_tag in robots:
                report(
                    name,
                    path,
                    f"container tag {c_tag!r} is already a robot's tag",
                    "endpoint-tag-clash",
                )
            containers.declare((user[name], c_tag), name, path, entry, f"container {c_tag!r}")

    def check_container_ref(file: str, path: str, c_tag: object, what: str) -> None:
        if (user[file], c_tag) not in containers:
            report(
                file,
                path,
                f"{what} names container {c_tag!r}, which no file of its user declares",
                "unknown-container",
            )

    nodes = _Declarations("node", report)
    parameters = _Declarations("parameter", report)
    for name, config in files_:
        for key, field, declared in (("nodes", "nTag", nodes), ("parameters", "name", parameters)):
            what = declared.kind
            for index, entry in _entries(config, key):
                path = f"{key}[{index}]"
                c_tag, tag = entry.get("cTag"), entry.get(field)
                check_container_ref(name, path, c_tag, f"{what} {tag!r}")
                label = f"{what} {tag!r} in container {c_tag!r}"
                declared.declare((user[name], c_tag, tag), name, path, entry, label)

    interfaces = _Declarations("interface", report)
    for name, config in files_:
        for index, entry in _entries(config, "interfaces"):
            path = f"interfaces[{index}]"
            e_tag, i_tag, i_type = entry.get("eTag"), entry.get("iTag"), entry.get("iType")
            label = f"interface {e_tag}/{i_tag}"
            kind = _role_and_suffix(i_type)
            if e_tag in robots:
                if kind is not None and kind[1] not in ROBOT_SUFFIXES:
                    report(
                        name,
                        f"{path}.iType",
                        f"{label} is on robot {e_tag!r}: a robot endpoint takes "
                        f"{kind[0]}Converter or {kind[0]}Forwarder, not {i_type}",
                        "interface-type-on-robot",
                    )
            elif (user[name], e_tag) in containers:
                if kind is not None and kind[1] not in CONTAINER_SUFFIXES:
                    report(
                        name,
                        f"{path}.iType",
                        f"{label} is on container {e_tag!r}: a container endpoint takes "
                        f"{kind[0]}Interface, not {i_type}",
                        "interface-type-on-container",
                    )
            else:
                report(
                    name,
                    f"{path}.eTag",
                    f"{label}: endpoint {e_tag!r} is neither a declared container nor a "
                    "robot of this set",
                    "unknown-endpoint",
                )
            interfaces.declare((user[name], e_tag, i_tag), name, path, entry, label)

    seen: dict[tuple[object, frozenset[object]], str] = {}  # connected pairs, across files
    for name, config in files_:
        for index, entry in _entries(config, "connections"):
            path = f"connections[{index}]"
            tags = [entry.get("tagA"), entry.get("tagB")]
            ends: list[Document] = []
            for key, tag in zip(("tagA", "tagB"), tags, strict=True):
                parts = tag.split("/") if isinstance(tag, str) else []
                if len(parts) != 2:
                    report(
                        name,
                        f"{path}.{key}",
                        f"{tag!r} is not of the form eTag/iTag",
                        "malformed-tag",
                    )
                    continue
                interface = interfaces.get((user[name], *parts))
                if interface is None:
                    report(
                        name,
                        f"{path}.{key}",
                        f"{tag} names no declared interface (no file of user "
                        f"{user[name]!r} declares interface {parts[1]!r} on endpoint "
                        f"{parts[0]!r})",
                        "unresolved-tag",
                    )
                else:
                    ends.append(interface)
            if all(isinstance(tag, str) for tag in tags):
                pair = (user[name], frozenset(tags))
                if len(pair[1]) == 1:
                    report(name, path, f"connects {tags[0]} to itself", "self-connection")
                elif pair in seen:
                    report(
                        name,
                        path,
                        f"{tags[0]} and {tags[1]} are already connected by {seen[pair]}",
                        "duplicate-connection",
                    )
                else:
                    seen[pair] = path if len(files_) == 1 else f"{name}: {path}"
            if len(ends) != 2:
                continue
            a, b = ends
            kind_a, kind_b = _role_and_suffix(a.get("iType")), _role_and_suffix(b.get("iType"))
            if kind_a and kind_b and frozenset({kind_a[0], kind_b[0]}) not in CONNECTABLE:
                report(
                    name,
                    path,
                    f"{tags[0]} ({a.get('iType')}) cannot be connected to {tags[1]} "
                    f"({b.get('iType')}): only "
                    + " or ".join(f"{first} with {second}" for first, second in PAIRS),
                    "unconnectable-pair",
                )
            if a.get("iCls") != b.get("iCls"):
                report(
                    name,
                    path,
                    f"{tags[0]} carries {a.get('iCls')} but {tags[1]} carries "
                    f"{b.get('iCls')}: both sides must have the same iCls",
                    "message-class-mismatch",
                )
    return sorted(problems)
