"""zenoh-bridge-ros2dds configurations: exactly the topics and services that cross.

Which data crosses which boundary is the wiring the Rapyuta files are made of (every
flow from the node producing it to each node consuming it, over the placement of
:mod:`spl.resolver.placement`): a flow whose two nodes run in different places (a
robot, or one instance of a cloud container) crosses. For each place, the bridge's
``allow`` lists (the keys of the bridge's DEFAULT_CONFIG.json5) hold:

- ``publishers``: topics produced here and consumed elsewhere (routed into Zenoh);
- ``subscribers``: topics produced elsewhere and consumed here (routed out of Zenoh);
- ``service_clients``: services called here and served elsewhere;
- ``service_servers``: services served here and called from elsewhere;
- ``action_servers`` / ``action_clients``: empty (the models have no actions).

Every list is written, empty or not: in an ``allow`` block a list left out means
*nothing* of that kind, so the bridge routes exactly these names and nothing
robot-local. Each entry is a regular expression the bridge matches against the whole
name; ROS names hold no regular-expression character, so a name is its own pattern.

Topology: one Zenoh router (``zenohd``, in the cloud) that robots connect to as
clients, at the host of their endpoint's URL, port 7447, authenticated with the
endpoint's user and the password named by ``password env`` (written ``${VAR}``, to be
substituted at deployment as in the Rapyuta files); the router connects to every cloud
instance's bridge, which runs in router mode next to its nodes. Multicast scouting is
off everywhere: each bridge talks to exactly the routers written here.

Zenoh carries a topic under one key, its ROS name, to every bridge that allows it. The
architecture can ask more than that: a bridge that renames (``/camera/image_raw`` on
the robot, ``/harvester/camera/image_raw`` in the cloud), or two places publishing one
name where a consumer must receive only one of them. Such a product is not *carried*:
:class:`Transport` says why (``reason``) and no configuration is produced for it,
rather than one that would deliver data the model does not connect.
"""

from __future__ import annotations

import json
import re
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any

from spl import __version__
from spl.diagnostics import Diagnostic, ModelError, location_of
from spl.generators.kubernetes_names import instance_names
from spl.resolver.placement import Placement
from spl.resolver.wiring import Wiring

ZENOH_PORT = 7447
ROUTER_FILE = "zenoh-router"  # zenoh/zenoh-router.json5
USERS_FILE = "/run/zenoh/users"
KINDS = (
    "publishers",
    "subscribers",
    "service_servers",
    "service_clients",
    "action_servers",
    "action_clients",
)
ROS_NAME = re.compile(r"[A-Za-z0-9_/~]+")
_URL_HOST = re.compile(r"wss?://([A-Za-z0-9.-]+)")


@dataclass
class Transport:
    """The Zenoh configuration of a product, or why Zenoh cannot carry it."""

    robot_configs: dict[str, str] = field(default_factory=dict)  # robotID -> JSON5
    cloud_configs: dict[str, str] = field(default_factory=dict)  # instance tag -> JSON5
    router_config: str = ""
    credentials: list[tuple[str, str]] = field(default_factory=list)  # (user, VAR)
    robot_files: dict[str, str] = field(default_factory=dict)  # robotID -> container
    reason: str | None = None

    @property
    def carried(self) -> bool:
        return self.reason is None


@dataclass
class _Crossings:
    """Per place tag and kind, the names crossing; and who feeds whom, per name."""

    allow: dict[str, dict[str, set[str]]] = field(
        default_factory=lambda: defaultdict(lambda: {kind: set() for kind in KINDS})
    )
    topic_flows: set[tuple[str, str, str]] = field(default_factory=set)  # (name, from, to)
    call_flows: set[tuple[str, str, str]] = field(default_factory=set)  # (name, caller, server)
    renames: list[str] = field(default_factory=list)


def _crossings(wiring: Wiring) -> _Crossings:
    """The crossings of every robot's view, once each."""
    found = _Crossings()
    seen = set()
    for robot in wiring.placement.robots:
        for crossing in wiring.crossings(robot):
            source, target = crossing.source.tag, crossing.target.tag
            a, b = crossing.source_name, crossing.target_name
            key = (crossing.kind, source, target, a, b)
            if key in seen:
                continue
            seen.add(key)
            if a != b:
                found.renames.append(
                    f"the {crossing.kind} {a} of {source} arrives in {target} as {b}, and a "
                    f"zenoh bridge carries a {crossing.kind} under one name"
                )
            elif crossing.kind == "topic":
                found.allow[source]["publishers"].add(a)
                found.allow[target]["subscribers"].add(b)
                found.topic_flows.add((a, source, target))
            else:
                found.allow[source]["service_clients"].add(a)
                found.allow[target]["service_servers"].add(b)
                found.call_flows.add((a, source, target))
    return found


def _unconnected(found: _Crossings) -> list[str]:
    """Deliveries one Zenoh network would make that the architecture does not."""
    problems = []
    for kind_out, kind_in, flows, verb in (
        ("publishers", "subscribers", found.topic_flows, "deliver"),
        ("service_clients", "service_servers", found.call_flows, "route calls of"),
    ):
        names = sorted({flow[0] for flow in flows})
        for name in names:
            sources = sorted(t for t, lists in found.allow.items() if name in lists[kind_out])
            targets = sorted(t for t, lists in found.allow.items() if name in lists[kind_in])
            if kind_in == "service_servers" and len(targets) > 1:
                problems.append(f"{name} is served by {' and '.join(targets)}")
                continue
            for source in sources:
                for target in targets:
                    if source != target and (name, source, target) not in flows:
                        problems.append(
                            f"zenoh would {verb} {name} from {source} to {target}, which "
                            "the architecture does not connect"
                        )
    return problems


def _json5(document: dict[str, Any], what: str) -> str:
    header = (
        f"// {what}, generated by spl-robotics {__version__}. Edit the models, not this file.\n"
    )
    return header + json.dumps(document, indent=2, sort_keys=False) + "\n"


def _allow(lists: dict[str, set[str]]) -> dict[str, list[str]]:
    for names in lists.values():
        for name in names:
            if not ROS_NAME.fullmatch(name):
                raise ModelError(
                    [Diagnostic(None, f"ROS name {name!r} cannot be a bridge pattern")]
                )
    return {kind: sorted(lists[kind]) for kind in KINDS}


def _robot_document(
    robot: Any,
    robot_id: str,
    lists: dict[str, set[str]] | None,
    users: dict[str, tuple[str, Any]],
    errors: list[Diagnostic],
) -> dict[str, Any] | None:
    """A robot's bridge: a client of the cloud's router, at its endpoint URL's host."""
    endpoint = robot.endpoint
    where = location_of(endpoint) or location_of(robot)
    if robot_id == ROUTER_FILE:
        errors.append(Diagnostic(where, f"robot_id {robot_id!r} is the Zenoh router's file name"))
        return None
    match = _URL_HOST.match(endpoint.url or "") if endpoint is not None else None
    if match is None:
        if lists:  # something crosses: the bridge needs the cloud's address
            errors.append(
                Diagnostic(
                    where,
                    f"robot container {robot.name} exchanges data with the cloud but its "
                    "endpoint has no url: its Zenoh bridge needs the cloud's address",
                )
            )
        return None
    document: dict[str, Any] = {
        "plugins": {"ros2dds": {"allow": _allow(lists or {kind: set() for kind in KINDS})}},
        "mode": "client",
        "connect": {"endpoints": [f"tcp/{match.group(1)}:{ZENOH_PORT}"]},
        "scouting": {"multicast": {"enabled": False}},
    }
    if endpoint.user and endpoint.passwordEnv:
        variable = endpoint.passwordEnv
        known = users.setdefault(endpoint.user, (variable, robot))
        if known[0] != variable:
            errors.append(
                Diagnostic(
                    where,
                    f"user {endpoint.user} authenticates with password env {variable} here "
                    f"and {known[0]} in robot container {known[1].name}: the Zenoh router "
                    "keeps one password per user",
                )
            )
        document["transport"] = {
            "auth": {"usrpwd": {"user": endpoint.user, "password": f"${{{variable}}}"}}
        }
    return document


def transport(system: Any) -> Transport:
    """The bridges of every robot and cloud instance, the router, or why not carried."""
    errors: list[Diagnostic] = []
    placement = Placement(system, errors)
    wiring = Wiring(system, placement, errors)
    instances = {i.place.tag: i for i in placement.cloud_instances()}
    services = instance_names(list(instances.values()), errors)
    found = _crossings(wiring)  # reports type clashes while it follows the flows
    if errors:
        raise ModelError(list(dict.fromkeys(errors)))
    problems = found.renames + _unconnected(found)
    if problems:
        return Transport(reason="; ".join(sorted(set(problems))))
    result = Transport()
    for tag in sorted(found.allow):
        if tag not in instances:
            continue
        result.cloud_configs[tag] = _json5(
            {
                "plugins": {
                    "ros2dds": {"ros_localhost_only": True, "allow": _allow(found.allow[tag])}
                },
                "mode": "router",
                "listen": {"endpoints": [f"tcp/[::]:{ZENOH_PORT}"]},
                "scouting": {"multicast": {"enabled": False}},
            },
            f"zenoh-bridge-ros2dds configuration of cloud instance {tag}",
        )
    users: dict[str, tuple[str, Any]] = {}
    for robot in placement.robots:
        robot_id = placement.robot_ids[id(robot)]
        lists = found.allow.get(robot_id)
        document = _robot_document(robot, robot_id, lists, users, errors)
        if document is not None:
            result.robot_configs[robot_id] = _json5(
                document, f"zenoh-bridge-ros2dds configuration of robot {robot.name} ({robot_id})"
            )
            result.robot_files[robot_id] = robot.name
    if errors:
        raise ModelError(list(dict.fromkeys(errors)))
    credentials = {(user, variable) for user, (variable, _) in users.items()}
    result.credentials = sorted(credentials)
    router: dict[str, Any] = {
        "mode": "router",
        "listen": {"endpoints": [f"tcp/[::]:{ZENOH_PORT}"]},
        "connect": {
            "endpoints": [f"tcp/{services[tag]}:{ZENOH_PORT}" for tag in result.cloud_configs]
        },
        "scouting": {"multicast": {"enabled": False}},
    }
    if result.credentials:
        router["transport"] = {"auth": {"usrpwd": {"dictionary_file": USERS_FILE}}}
    result.router_config = _json5(router, "Zenoh router (zenohd) configuration of the cloud")
    return result
