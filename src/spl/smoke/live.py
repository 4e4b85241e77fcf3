"""The live graph of each container, read from its master, compared with the plan.

Each master is asked over its XML-RPC API (``getSystemState``, ``getTopicTypes``,
``getParam``; no rospy needed on this side), and each stand-in's status file says what
its interfaces resolved to and what they received or were answered. The comparison
gives one :class:`Row` per modelled interface and parameter, plus a failing row for
everything live that the model does not have: an unexpected node, publication,
subscription or service.
"""

from __future__ import annotations

import http.client
import json
import xmlrpc.client
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from spl.core.diagnostics import counted
from spl.metamodels.interface_kinds import FAMILIES, KINDS, InterfaceKind, side
from spl.smoke.plan import ContainerPlan, Interface, NodePlan

CALLER = "/spl_smoke"
NOT_MODELLED = "not in the model"
ROSOUT = "/rosout"
# What every rospy node and the core register by themselves.
INFRASTRUCTURE_TOPICS = frozenset({"/rosout", "/rosout_agg"})
INFRASTRUCTURE_SERVICE_SUFFIXES = ("/get_loggers", "/set_logger_level")


class _Transport(xmlrpc.client.Transport):
    def make_connection(self, host: Any) -> http.client.HTTPConnection:
        connection = super().make_connection(host)
        connection.timeout = 2.0
        return connection


class Master:
    """A ROS master's XML-RPC API, with a short timeout on every call."""

    def __init__(self, uri: str) -> None:
        self.uri = uri
        self.proxy = xmlrpc.client.ServerProxy(uri, transport=_Transport())

    def _call(self, method: str, *args: Any) -> Any:
        code, message, value = getattr(self.proxy, method)(CALLER, *args)
        if code != 1:
            raise LookupError(message)
        return value

    def pid(self) -> int | None:
        """The process id of the master answering at this URI, or None when none does."""
        try:
            return int(self._call("getPid"))
        except (OSError, xmlrpc.client.Error, LookupError, ValueError):
            return None

    def graph(self) -> LiveGraph:
        publishers, subscribers, services = self._call("getSystemState")
        return LiveGraph(
            {topic: set(nodes) for topic, nodes in publishers},
            {topic: set(nodes) for topic, nodes in subscribers},
            {name: set(nodes) for name, nodes in services},
            dict(self._call("getTopicTypes")),
        )

    def param(self, name: str) -> tuple[bool, Any]:
        try:
            return True, self._call("getParam", name)
        except LookupError:
            return False, None


@dataclass
class LiveGraph:
    publishers: dict[str, set[str]] = field(default_factory=dict)
    subscribers: dict[str, set[str]] = field(default_factory=dict)
    services: dict[str, set[str]] = field(default_factory=dict)
    types: dict[str, str] = field(default_factory=dict)

    def nodes(self) -> set[str]:
        every = [*self.publishers.values(), *self.subscribers.values(), *self.services.values()]
        return set().union(*every) - {ROSOUT}

    def registered(self, kind: InterfaceKind) -> dict[str, set[str]] | None:
        """The nodes the master lists with an interface of ``kind``, by topic or service
        name; None for a caller, which the ROS 1 master does not register, and for a kind
        the master knows only as its topics (an action, ``Family.ros1_topics``)."""
        if kind.family.ros1_topics:
            return None
        if kind.publishes:
            return self.publishers
        if kind.subscribes:
            return self.subscribers
        return self.services if kind.serves else None


@dataclass(frozen=True)
class Row:
    container: str
    node: str
    interface: str
    topic: str
    expected: str
    seen: str
    ok: bool

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def read_statuses(folder: Path) -> dict[str, dict[str, Any]]:
    """Node ROS name -> the last status its stand-in wrote (files in ``folder``)."""
    statuses = {}
    for path in sorted(folder.glob("*.json")) if folder.is_dir() else ():
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue  # replaced atomically; a read racing the rename is retried next poll
        statuses[data.get("node", path.stem)] = data
    return statuses


def short(identifier: str, container: str) -> str:
    """``Robot.RGBCameraL.image`` shown as ``RGBCameraL.image`` inside container Robot."""
    prefix = f"{container}."
    return identifier[len(prefix) :] if identifier.startswith(prefix) else identifier


def compare(
    plan: ContainerPlan,
    graph: LiveGraph | None,
    statuses: dict[str, dict[str, Any]],
    params: dict[str, tuple[bool, Any]],
) -> list[Row]:
    """The rows of one container: every modelled interface and parameter, then what the
    live graph has that the model does not."""
    graph = graph or LiveGraph()
    rows: list[Row] = []
    for node in plan.nodes:
        status = statuses.get(node.ros_name)
        if node.role == "generated":  # the bundle's own node: no status, its graph entry
            if node.ros_name not in graph.nodes():
                rows.append(Row(plan.name, node.name, "(node)", node.ros_name, "running",
                                "not registered with the master", False))  # fmt: skip
            for interface in node.interfaces:
                rows.append(_generated_row(plan, node, interface, graph))
            continue
        if status is None or status.get("error"):
            seen = status["error"] if status else "not running"
            rows.append(Row(plan.name, node.name, "(node)", node.ros_name, "running", seen, False))
        for interface in node.interfaces:
            entry = (status or {}).get("interfaces", {}).get(interface.name)
            rows.append(_interface_row(plan, node, interface, graph, entry))
        for parameter in node.parameters:
            present, value = params.get(parameter.ros_name, (False, None))
            seen = repr(value) if present else "not set"
            rows.append(
                Row(plan.name, node.name, f"param {parameter.name}", parameter.ros_name,
                    repr(parameter.value), seen, present and value == parameter.value)
            )  # fmt: skip
    rows += _unexpected(plan, graph, statuses)
    return rows


def _interface_row(
    plan: ContainerPlan,
    node: NodePlan,
    interface: Interface,
    graph: LiveGraph,
    entry: dict[str, Any] | None,
) -> Row:
    kind, topic = interface.kind, interface.ros_name
    entry = entry or {}
    notes = []
    resolved = entry.get("resolved")
    if resolved and resolved != topic:
        notes.append(f"bound to {resolved}")
    registered = True
    for side_kind, name, part_type in registrations(interface):
        registry = graph.registered(side_kind)
        if registry is not None and node.ros_name not in registry.get(name, ()):
            notes.append(f"not registered on {name}")
            registered = False
        elif side_kind.on_topic and name != topic and graph.types.get(name) != part_type:
            # a part that is a topic (a master lists no service's type)
            notes.append(f"{name} type {graph.types.get(name)}")
            registered = False
    ok = registered
    words = kind.family.answers  # how its calls are said: an action's goals, results...
    if kind.publishes:
        expected = f"{kind.keyword} {interface.type}"
        live_type = graph.types.get(topic)
        if registered and live_type != interface.type:
            notes.append(f"type {live_type}")
            ok = False
        seen = f"{kind.keyword} {live_type} ({entry.get('sent', 0)} sent)" if ok else ""
    elif kind.subscribes:
        expected = _sources_text(interface, plan.name)
        received = entry.get("received", {})
        missing = [s for s in interface.sources if s not in received]
        extra = [s for s in received if s not in interface.sources]
        starved = interface.required and bool(missing)
        ok = ok and not starved and not extra
        seen = ", ".join(f"from {short(s, plan.name)} ({n})" for s, n in sorted(received.items()))
        seen = seen or "nothing received"
        if missing and received:
            notes.append("nothing from " + ", ".join(short(s, plan.name) for s in missing))
        if extra:
            notes.append("not in the model: " + ", ".join(short(s, plan.name) for s in extra))
    elif kind.serves:
        expected = f"{kind.keyword} {interface.type}"
        answered = counted(entry.get("served", 0), words.call)
        seen = f"{kind.keyword} ({answered} answered)" if registered else ""
    else:
        expected = (
            f"{words.expected} from {short(interface.server, plan.name)}"
            if interface.server
            else f"nothing: {interface.gap}"
            if interface.gap
            else ("an answer (no server in the model)" if interface.required else "calls forwarded")
        )
        answers = entry.get("answered_by", {})
        feedback = entry.get("feedback_from", {}) if words.back else {}
        seen = ", ".join(
            [f"{words.answered} {short(s, plan.name)} ({n})" for s, n in sorted(answers.items())]
            + [
                f"{words.back} from {short(s, plan.name)} ({n})"
                for s, n in sorted(feedback.items())
            ]
        )
        wrong = [s for s in {*answers, *feedback} if s != interface.server]
        reached = interface.server in answers and (not words.back or interface.server in feedback)
        ok = ok and not wrong and (reached or not interface.required)
        if not seen:
            error = entry.get("last_error")
            seen = f"no answer: {error}" if error else "no answer"
            if not interface.required:
                seen = "no calls forwarded"
    seen = "; ".join([s for s in (seen, *notes) if s])
    return Row(plan.name, node.name, interface.name, topic, expected, seen, ok)


def _generated_row(plan: ContainerPlan, node: NodePlan, interface: Interface,
                   graph: LiveGraph) -> Row:  # fmt: skip
    """A generated writer's or reader's interface: registered where the model binds it,
    with the model's type (the data it moves is checked by the data path's rows)."""
    registry = graph.registered(interface.kind) or {}
    registered = node.ros_name in registry.get(interface.ros_name, ())
    live_type = graph.types.get(interface.ros_name)
    ok = registered and live_type == interface.type
    verb = interface.kind.keyword
    seen = f"{verb} {live_type}" if registered else f"not registered on {interface.ros_name}"
    return Row(plan.name, node.name, interface.name, interface.ros_name,
               f"{verb} {interface.type} (generated node)", seen, ok)  # fmt: skip


def _sources_text(interface: Interface, container: str) -> str:
    if interface.sources:
        return "from " + ", ".join(short(s, container) for s in interface.sources)
    if interface.gap:  # resolve's verdict (or the model's reason); not a failure here
        return f"nothing: {interface.gap}"
    return "nothing"


def _unexpected(
    plan: ContainerPlan, graph: LiveGraph, statuses: dict[str, dict[str, Any]]
) -> list[Row]:
    expected = {node.ros_name for node in plan.nodes}
    rows = []
    for ros_name in sorted(graph.nodes() - expected):
        rows.append(Row(plan.name, ros_name, "(node)", ros_name, NOT_MODELLED, "running",
                        False))  # fmt: skip
    wanted = {
        (kind, name, node.ros_name)
        for node in plan.nodes
        for i in node.interfaces
        for kind, name, _ in registrations(i)
    }
    names = {node.ros_name: node.name for node in plan.nodes}
    for kind in KINDS:
        registry = graph.registered(kind)
        if registry is None:
            continue
        for topic, nodes in sorted(registry.items()):
            if topic in INFRASTRUCTURE_TOPICS or topic.endswith(INFRASTRUCTURE_SERVICE_SUFFIXES):
                continue
            for ros_name in sorted(nodes - {ROSOUT}):
                if (kind, topic, ros_name) in wanted:
                    continue
                node = names.get(ros_name, ros_name)
                interface = _interface_bound_to(statuses.get(ros_name), topic)
                rows.append(
                    Row(
                        plan.name,
                        node,
                        interface,
                        topic,
                        NOT_MODELLED,
                        f"{kind.keyword} {graph.types.get(topic, '')}".strip(),
                        False,
                    )
                )
    return rows


def registrations(interface: Interface) -> list[tuple[InterfaceKind, str, str]]:
    """``(kind, ROS name, type)`` of what the master lists for ``interface``: the
    interface itself, or, for a kind that is its family's ROS 1 interfaces (an action,
    the five topics of actionlib), each part under its name with the side of the part's
    carrier that sends it or takes it (a client publishes goals and cancels, its server
    the rest; a part that is a service is served by the server, called by the client)."""
    parts = interface.kind.family.ros1_topics
    if not parts:
        return [(interface.kind, interface.ros_name, interface.type)]
    found = []
    for part in parts:
        sends = part.from_consumer != interface.kind.provides
        found.append(
            (side(part.carrier, sends == part.carrier.flows_from_provider),
             f"{interface.ros_name}/{part.suffix}", part.message_of(interface.type))
        )  # fmt: skip
    return found


def _interface_bound_to(status: dict[str, Any] | None, topic: str) -> str:
    """The interface of an unexpected row: the node's interface resolved to ``topic``,
    or to the action ``topic`` is one of the topics of (``NAME/goal`` ... ``NAME/result``,
    ``Family.ros1_topics``); else that action, by family and name; else "?"."""
    group, _, last = topic.rpartition("/")
    families = [f for f in FAMILIES if last in {p.suffix for p in f.ros1_topics}]
    for name, entry in ((status or {}).get("interfaces") or {}).items():
        if entry.get("resolved") == topic or (
            families and group and entry.get("resolved") == group
        ):
            return name
    return f"{families[0]} {group}" if families and group else "?"
