"""Building a smoke plan from a bundle (the plan's types are :mod:`spl.smoke.plan`'s):
the containers, nodes, interfaces and parameters of ``resolved.tsm`` with the ROS names
they must have; the flow table's expectations and relays; and, for the data path, the
data-typed messages, the values stand-in publishers send and the probes on readers'
topics."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from spl.core.diagnostics import Diagnostic, ModelError
from spl.metamodels import tsm
from spl.metamodels.interface_kinds import kind_of, side
from spl.resolver.architecture.checks import input_gap
from spl.resolver.architecture.flows import FlowTable, container_of
from spl.resolver.architecture.product import topic_ros_name
from spl.resolver.architecture.ros_names import remappings, server_ros_name
from spl.smoke.plan import (
    ContainerPlan,
    Interface,
    NodePlan,
    Parameter,
    Relay,
    SmokePlan,
    endpoint_name,
    join,
    namespace_of,
    node_ros_name,
)

DATA_MESSAGES = 12  # messages a stand-in publisher sends on a writer's topic
ROS_FIELD_TYPES = {"double": "float64", "int": "int64", "string": "string", "bool": "bool"}
TRACKING = "string source\nstring route\nuint32 seq\n"


def load_plan(bundle: Path, generated: bool = False, actions: bool = True) -> SmokePlan:
    """The plan of the bundle in folder ``bundle``; a ModelError when it is not one.
    ``generated``: the bundle's own writers and readers run (the data path), not
    stand-ins. ``actions``: actionlib is there to play the actions; without it they are
    left out of the plan (the rehearsal warns, docs/smoke.md "Actions")."""
    from spl.pipeline import read_bundle

    system, product = read_bundle(bundle)
    fields = data_fields(system)
    messages = {
        kind: f"string TYPE={kind}\n"
        + "".join(f"{ROS_FIELD_TYPES[t]} {name}\n" for name, t in names)
        + TRACKING
        for kind, names in fields.items()
    }
    _refuse_unrehearsed(system)
    containers = _containers(system, generated)
    if not actions:
        _leave_out_actions(containers)
    _expect_values(containers, fields)
    _probe_readers(containers)
    return SmokePlan(product, containers, messages)


def _refuse_unrehearsed(system: Any) -> None:
    """A bundle with an interface of a kind no stand-in plays (``smoke_role`` None in the
    registry: a kind added before its stand-in, docs/architecture.md "Where to add ...";
    every kind has one today) is refused before anything starts, in one line naming
    each such interface, rather than rehearsed without it."""
    unplayed = [
        f"{kind_of(i).title} {container.name}.{node.name}.{i.name}"
        for container in system.containers
        for node in container.nodes
        for i in node.interfaces
        if kind_of(i).smoke_role is None
    ]
    if unplayed:
        raise ModelError(
            [
                Diagnostic(
                    None,
                    f"spl smoke cannot rehearse this bundle yet: it has no stand-in for "
                    f'{", ".join(unplayed)} (docs/architecture.md, "Where to add ...")',
                )
            ]
        )


def actions_of(system: Any) -> list[str]:
    """The node interfaces of ``system`` that actionlib plays (``Family.needs_actionlib``),
    as a message names them, in model order."""
    return [
        f"{kind_of(i).title} {container.name}.{node.name}.{i.name}"
        for container in system.containers
        for node in container.nodes
        for i in node.interfaces
        if kind_of(i).family.needs_actionlib
    ]


def _leave_out_actions(plans: list[ContainerPlan]) -> None:
    for container in plans:
        for node in container.nodes:
            node.interfaces = [i for i in node.interfaces if not i.kind.family.needs_actionlib]


def data_fields(system: Any) -> dict[str, list[tuple[str, str]]]:
    """The topic types writers and readers use, each with its data type's fields (which
    the generated nodes read and set by name): the messages of those topics carry them,
    then the stand-ins' tracking fields (the constant keeps two types' definitions and
    md5sums apart)."""
    T = tsm()
    found: dict[str, list[tuple[str, str]]] = {}
    for container in system.containers:
        for node in container.nodes:
            if not isinstance(node, T.Writer | T.Reader) or node.dataType is None:
                continue
            for interface in node.interfaces:
                found.setdefault(
                    _type(interface), [(f.name, f.type.name) for f in node.dataType.fields]
                )
    return found


def _expect_values(plans: list[ContainerPlan], fields: dict[str, list[tuple[str, str]]]) -> None:
    """A stand-in publisher on a data-typed topic sends a known run of values, once the
    subscribers its data must reach in its container are connected (none lost to ROS
    connecting late)."""
    for container in plans:
        interfaces = [i for n in container.nodes for i in n.interfaces]
        for publisher in interfaces:
            if not publisher.kind.publishes or publisher.endpoint or publisher.type not in fields:
                continue
            waiting = [
                i for i in interfaces
                if i.kind.subscribes and i.ros_name == publisher.ros_name
                and publisher.id in i.sources
            ]  # fmt: skip
            publisher.values = {
                "fields": [list(pair) for pair in fields[publisher.type]],
                "count": DATA_MESSAGES,
                "wait_for": len(waiting),
            }


PROBE = "spl_probe"


def _probe_readers(plans: list[ContainerPlan]) -> None:
    """A subscriber of the rehearsal's own on the topic of each generated reader that no
    node of its container subscribes to: what the reader publishes is checked too."""
    for container in plans:
        interfaces = [i for n in container.nodes for i in n.interfaces]
        for node in [n for n in container.nodes if n.role == "generated"]:
            for publisher in (i for i in node.interfaces if i.kind.publishes):
                if any(publisher.id in i.sources for i in interfaces):
                    continue
                taken = {n.name for n in container.nodes} | {n.ros_name for n in container.nodes}
                name = endpoint_name(taken, container.namespace, f"{PROBE}_{node.name}")
                probe = NodePlan(container.name, name,
                                 node_ros_name(container.namespace, name), "probe")  # fmt: skip
                probe.interfaces.append(
                    Interface(container.name, name, publisher.name,
                              side(publisher.kind.family, False), publisher.type,
                              publisher.ros_name, sources=(publisher.id,))
                )  # fmt: skip
                container.nodes.append(probe)


def _containers(system: Any, generated: bool) -> list[ContainerPlan]:
    T = tsm()
    plans = []
    for container in system.containers:
        namespace = namespace_of(container)
        plan = ContainerPlan(container.name, namespace)
        for node in container.nodes:
            data_client = isinstance(node, T.Writer | T.Reader)
            bound = dict(remappings(node, system))
            node_plan = NodePlan(
                container.name,
                node.name,
                node_ros_name(namespace, node.name),
                "generated" if data_client and generated else "launched",
            )
            for interface in node.interfaces:
                ros_name = join(namespace, bound.get(interface.name, interface.name))
                node_plan.interfaces.append(
                    Interface(
                        container.name,
                        node.name,
                        interface.name,
                        kind_of(interface),
                        _type(interface),
                        ros_name,
                        # an interface the model leaves unconnected (`subscribes x : T`,
                        # no topic in this product) is wired to nothing: nothing expected
                        required=interface.name in bound,
                    )
                )
            for parameter in node.parameters:
                if parameter.value is not None:
                    node_plan.parameters.append(
                        Parameter(
                            parameter.name,
                            f"{node_plan.ros_name}/{parameter.name}",
                            _typed(parameter.type.name, parameter.value),
                        )
                    )
            plan.nodes.append(node_plan)
        if container.endpoint is not None and container.endpoint.interfaces:
            taken = {n.name for n in plan.nodes} | {n.ros_name for n in plan.nodes}
            name = endpoint_name(taken, namespace)
            plan.nodes.append(_endpoint(container, namespace, system, name))
        plans.append(plan)
    _expect_flows(system, plans)
    return plans


def _type(interface: Any) -> str:
    """Its own type, else that of the topic or server it is bound to; "" if none."""
    bound = kind_of(interface).bound_to(interface)
    return interface.type or (bound.type if bound else None) or ""


def _typed(kind: str, text: str) -> Any:
    if kind == "int":
        return int(text, 10)
    if kind == "double":
        return float(text)
    if kind == "bool":
        return text == "true"
    if kind == "yaml":
        return yaml.safe_load(text)
    return text


def _endpoint(container: Any, namespace: str, system: Any, name: str) -> NodePlan:
    node = NodePlan(container.name, name, node_ros_name(namespace, name), "endpoint")
    forward: dict[int, tuple[str, str]] = {}
    peers: dict[int, list[tuple[str, str]]] = {}
    for connection in system.connections:
        source, target = connection.source, connection.target
        if kind_of(source).serves:  # a stand-in's one peer client
            forward.setdefault(id(source), (container_of(target).name, target.name))
            if kind_of(source).family.ros1_topics:  # answers come back as topics too
                peers.setdefault(id(target), []).append((container_of(source).name, source.name))
    for interface in container.endpoint.interfaces:
        kind = kind_of(interface)
        bound = kind.bound_to(interface)  # its topic, or the server it calls
        if kind.on_topic:
            ros_name = topic_ros_name(bound) if bound else interface.name
        elif kind.serves:  # a stand-in answers under the name of the server it stands for
            ros_name = server_ros_name(interface, system)
        else:
            ros_name = server_ros_name(bound, system) if bound else interface.name
        node.interfaces.append(
            Interface(
                container.name,
                name,
                interface.name,
                kind,
                _type(interface),
                join(namespace, ros_name),
                forward=forward.get(id(interface)),
                peers=tuple(peers.get(id(interface), ())),
                endpoint=True,
            )
        )
    return node


def _expect_flows(system: Any, plans: list[ContainerPlan]) -> None:
    """Fill in, from the flow table, the sources of every subscriber, the server of every
    client and the relays of every endpoint subscriber; mark the endpoint interfaces a
    flow passes as required."""
    T = tsm()
    endpoints = {c.name: c.endpoint.name for c in plans if c.endpoint is not None}
    by_id = {i.id: i for c in plans for n in c.nodes for i in n.interfaces}

    def plan_of(interface: Any) -> Interface:
        owner = interface.eContainer()
        node = endpoints[owner.eContainer().name] if isinstance(owner, T.Endpoint) else owner.name
        return by_id[f"{container_of(interface).name}.{node}.{interface.name}"]

    connection_ids = {id(c): f"c{n}" for n, c in enumerate(system.connections)}
    arriving: dict[tuple[str, str], set[str]] = {}  # (container, ROS name) -> publisher ids
    passes: dict[tuple[str, int], list[str]] = {}  # (endpoint subscriber id, conn) -> keys
    sources: dict[str, list[str]] = {}
    flows = FlowTable.of(system)
    for flow in flows:
        source, target = plan_of(flow.source), plan_of(flow.target)
        if not flow.kind.on_topic:  # a call: the client's answer comes from the server
            source.server = target.id
            for connection in flow.route:  # endpoint clients passing the calls on
                relay = plan_of(connection.target)
                relay.required, relay.server = True, target.id
            continue
        sources.setdefault(target.id, []).append(source.id)
        crossed: list[str] = []
        for connection in flow.route:
            key = f"{source.id}|{','.join(crossed)}"
            keys = passes.setdefault((plan_of(connection.source).id, id(connection)), [])
            if key not in keys:
                keys.append(key)
            crossed.append(connection_ids[id(connection)])
            arriving.setdefault(_topic(plan_of(connection.target)), set()).add(source.id)
    for interface in by_id.values():
        if interface.kind.publishes and not interface.endpoint:
            arriving.setdefault(_topic(interface), set()).add(interface.id)
    for interface in by_id.values():
        if interface.kind.subscribes and interface.endpoint:
            interface.sources = tuple(sorted(arriving.get(_topic(interface), ())))
            interface.required = bool(interface.sources)
        elif interface.kind.subscribes:
            interface.sources = tuple(sorted(set(sources.get(interface.id, ()))))
        elif interface.kind.calls and interface.endpoint and interface.server is None:
            interface.required = False  # no node client's calls pass through it
    for container in system.containers:  # resolve's verdict on inputs nothing feeds
        for node in container.nodes:
            for model_interface in node.interfaces:
                gap = input_gap(model_interface, flows)
                planned = plan_of(model_interface)
                if gap is not None:
                    planned.gap = f"{planned.kind.gap_word} in the model ({gap})"
                elif model_interface.external and not flows.feeding(model_interface):
                    planned.gap = f"fed from outside the architecture: {model_interface.external}"
                if planned.gap and planned.kind.calls:
                    planned.required = False  # no answer is expected: none is modelled
    for connection in system.connections:
        if kind_of(connection.source).subscribes:  # an endpoint subscriber relays
            endpoint = plan_of(connection.source)
            passed = passes.get((endpoint.id, id(connection)))
            if passed:
                sender = plan_of(connection.target)
                onward = Relay(sender.container, sender.name, connection_ids[id(connection)],
                               tuple(passed))  # fmt: skip
                endpoint.relays = (*endpoint.relays, onward)


def _topic(interface: Interface) -> tuple[str, str]:
    return interface.container, interface.ros_name
