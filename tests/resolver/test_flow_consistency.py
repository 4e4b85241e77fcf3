"""Every output tells the flow table's story (docs/semantics.md, "Flows"), on random lines
of two or more robots and cloud nodes of every sharing mode (tests/random_lines.py):

- the table itself is the resolved model's own reachability, computed here with a walk
  of its own over the pyecore model (publisher topic, endpoint connections, subscriber
  topics; a robot passes on only its own data; clients through stand-ins to servers);
- the Rapyuta connections carry exactly the table's flows between places, as each
  robot's deployment places them (private partitions per robot, withheld from other
  robots), derived here from the table and the sharing modes, between the private
  instances the placement deploys;
- the Zenoh allow lists, matched by key as the bridges match them, deliver exactly those,
  or the bundle says why Zenoh cannot carry the product;
- the smoke plan expects the table's sources and servers, and its relays, followed
  message by message as the stand-ins follow them, bring every publisher's data to
  exactly the subscribers the table feeds (no ROS started).

The fleets have actions too (robot clients sending goals to cloud servers through action
bridges, migrations moving either end): the table's action flows are the model's
client-to-server reachability, Rapyuta carries each as its five topics in their
directions, Zenoh pairs action_clients with action_servers, and the smoke plan's
stand-ins carry each goal along the route to its server and the answers back.
"""

from __future__ import annotations

import json
import tempfile
from collections import defaultdict
from pathlib import Path
from typing import Any

import json5
from hypothesis import event, given, settings, strategies as st, target

from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle, write_bundle
from spl.metamodels.interface_kinds import ACTION
from spl.resolver.architecture.flows import SERVICE, TOPIC, FlowTable
from spl.resolver.architecture.placement import Placement
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.ros_names import resolved_service_name, resolved_topic_name
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list
from spl.smoke.planning import load_plan

from support.hypothesis_budget import examples
from support.random_lines import fleet_specs, write_line

Delivery = tuple[str, str, str, str, str]  # kind, source place, name there, target place, name


def container(element: Any) -> Any:
    while element.eClass.name not in ("RobotContainer", "CloudContainer"):
        element = element.eContainer()
    return element


def is_robot(c: Any) -> bool:
    return c.eClass.name == "RobotContainer"


def name(interface: Any) -> str:
    return f"{container(interface).name}.{interface.eContainer().name}.{interface.name}"


# -- the table is the model's own reachability ---------------------------------------------
def reachability(system: Any) -> set[tuple[str, str, str]]:
    """(kind, source, target) of every delivery, walked here over the model."""
    topics_after: dict[int, list[Any]] = defaultdict(list)
    calls_after: dict[int, Any] = {}
    for c in system.connections:
        if c.source.eClass.name == "Subscriber":
            topics_after[id(c.source.topic)].append(c.target.topic)
        else:
            calls_after.setdefault(id(c.source), c.target)
    nodes = [n for c in system.containers for n in c.nodes]
    interfaces = [i for n in nodes for i in n.interfaces]
    found = set()
    for publisher in (i for i in interfaces if i.eClass.name == "Publisher" and i.topic):
        home, reached, todo = container(publisher.topic), {id(publisher.topic)}, [publisher.topic]
        while todo:
            topic = todo.pop()
            if is_robot(container(topic)) and container(topic) is not home:
                continue  # a robot passes on no data but its own
            for nxt in topics_after[id(topic)]:
                if id(nxt) not in reached:
                    reached.add(id(nxt))
                    todo.append(nxt)
        for subscriber in interfaces:
            if subscriber.eClass.name == "Subscriber" and id(subscriber.topic) in reached:
                found.add((TOPIC, name(publisher), name(subscriber)))
    calling = {"ServiceClient": SERVICE, "ActionClient": ACTION}
    for client in (i for i in interfaces if i.eClass.name in calling and i.server):
        server, seen = client.server, set()
        while server is not None and server.eContainer().eClass.name == "Endpoint":
            if id(server) in seen or id(server) not in calls_after:
                server = None
                break
            seen.add(id(server))
            server = calls_after[id(server)].server
        if server is not None:
            found.add((calling[client.eClass.name], name(client), name(server)))
    return found


# -- what the deployments must carry ---------------------------------------------------------
def expected_deliveries(product: ResolvedProduct) -> set[Delivery]:
    """The table's flows between places, from every robot's view, between the instances
    deployed: which private instances a robot gets is the placement's decision, itself
    checked against the flow chains in test_private_instances_random.py."""
    system = product.system
    deployed = {
        (instance.place.tag, node.name)
        for instance in Placement(system, [], flows=product.flows).cloud_instances()
        for node in instance.nodes
    }
    robots = [c for c in system.containers if is_robot(c)]
    rid = {id(r): r.endpoint.robotId for r in robots}
    linked: dict[int, set[int]] = defaultdict(set)
    for c in system.connections:
        a, b = container(c.source), container(c.target)
        linked[id(a)].add(id(b))
        linked[id(b)].add(id(a))
    by_id = {id(c): c for c in system.containers}
    found: set[Delivery] = set()
    for robot in robots:
        clouds, todo = set(), [id(robot)]
        while todo:
            for other in linked[todo.pop()]:
                if other not in clouds and not is_robot(by_id[other]):
                    clouds.add(other)
                    todo.append(other)
        view = {id(robot)} | clouds
        view |= {o for c in view for o in linked[c] if is_robot(by_id[o])}

        def place(interface: Any, robot: Any = robot) -> tuple[str, str, str]:
            """(tag, kind, owner)"""
            c, node = container(interface), interface.eContainer()
            if is_robot(c):
                return rid[id(c)], "robot", rid[id(c)]
            mode = node.sharing.name if node.sharing is not None else "private"
            owner = {"private": rid[id(robot)], "protected": c.group or c.name}.get(mode, "public")
            return f"{c.name}_{owner}", mode, owner

        for flow in product.flows:
            if id(flow.source_container) not in view or id(flow.target_container) not in view:
                continue
            source, target = place(flow.source), place(flow.target)

            def foreign(p: tuple[str, str, str], robot: Any = robot) -> bool:
                return p[1] == "robot" and p[2] != rid[id(robot)]

            if (foreign(source) and target[1] == "private") or (
                foreign(target) and source[1] == "private"
            ):
                continue  # a private partition serves its own robot alone
            ends = ((source, flow.source), (target, flow.target))
            if any(
                p[1] == "private" and (p[0], i.eContainer().name) not in deployed for p, i in ends
            ):
                continue  # an instance the robot does not get
            if flow.kind == TOPIC:
                a, b = (
                    resolved_topic_name(flow.source.topic),
                    resolved_topic_name(flow.target.topic),
                )
            else:
                a = resolved_service_name(flow.source.server, flow.source_container, system)
                b = resolved_service_name(flow.target, flow.target_container, system)
            if source[0] != target[0] or (flow.kind == TOPIC and a != b):
                found.add((flow.kind, source[0], a, target[0], b))
    return found


ACTION_TOPICS = (("goal", True), ("cancel", True), ("status", False), ("feedback", False),
                 ("result", False))  # actionlib's, and whether the client sends it  # fmt: skip


def as_topics(deliveries: set[Delivery]) -> set[Delivery]:
    """The deliveries a Rapyuta configuration makes of ``deliveries``: an action's five
    topics under its names, goals and cancels from the client's place, the rest back."""
    found = set()
    for kind, source, a, into, b in deliveries:
        if kind != ACTION:
            found.add((kind, source, a, into, b))
            continue
        for part, sent in ACTION_TOPICS:
            ends = ((source, f"{a}/{part}"), (into, f"{b}/{part}"))
            (p, x), (q, y) = ends if sent else ends[::-1]
            found.add((TOPIC, p, x, q, y))
    return found


def rapyuta_deliveries(files: dict[str, Any]) -> set[Delivery]:
    documents = [json.loads(d) for p, d in files.items() if p.startswith("rapyuta/")]
    interfaces = {
        f"{i['eTag']}/{i['iTag']}": i for doc in documents for i in doc.get("interfaces", ())
    }
    found = set()
    for doc in documents:
        for connection in doc.get("connections", ()):
            a, b = interfaces[connection["tagA"]], interfaces[connection["tagB"]]
            kind = TOPIC if a["iType"].startswith("Subscriber") else SERVICE
            assert b["iType"].startswith("Publisher" if kind == TOPIC else "ServiceClient")
            found.add((kind, a["eTag"], a["addr"], b["eTag"], b["addr"]))
    return found


def zenoh_deliveries(files: dict[str, Any]) -> set[Delivery]:
    """Pairs of bridges of two places whose keys (namespace + name) meet."""
    lists: dict[str, list] = {
        k: [] for k in ("publishers", "subscribers", "service_clients", "service_servers",
                        "action_clients", "action_servers")
    }  # fmt: skip
    for path, data in files.items():
        if not path.startswith("zenoh/") or not path.endswith(".json5"):
            continue
        place = path.removeprefix("zenoh/").removesuffix(".json5").split(".")[0]
        if place == "zenoh-router":
            continue
        plugin = json5.loads(data.decode())["plugins"]["ros2dds"]
        for kind, names in plugin["allow"].items():
            for ros_name in names if kind in lists else ():
                lists[kind].append((place, ros_name, plugin.get("namespace", "") + ros_name))
    found = set()
    for kind, out, into in ((TOPIC, "publishers", "subscribers"),
                            (SERVICE, "service_clients", "service_servers"),
                            (ACTION, "action_clients", "action_servers")):  # fmt: skip
        for source, a, key in lists[out]:
            for place, b, other in lists[into]:
                if key == other and source != place:
                    found.add((kind, source, a, place, b))
    return found


# -- what the rehearsal expects and relays ----------------------------------------------------
def check_smoke_plan(product: ResolvedProduct, folder: Path) -> None:
    plan = load_plan(folder)
    by_id = {i.id: i for i in plan.interfaces()}
    table = FlowTable.of(product.system)
    fed: dict[str, set[str]] = defaultdict(set)
    for flow in table:
        if flow.kind != TOPIC:
            assert by_id[name(flow.source)].server == name(flow.target)
            if flow.kind == ACTION:
                follow_goals(plan, by_id[name(flow.source)], by_id[name(flow.target)])
        else:
            fed[name(flow.target)].add(name(flow.source))
    for interface in by_id.values():
        if interface.kind.subscribes and not interface.endpoint:
            assert set(interface.sources) == fed[interface.id], interface.id
    # follow the relays as the stand-ins do: (publisher id, route so far) at a topic
    endpoints = {c.name: c.endpoint for c in plan.containers if c.endpoint is not None}
    arrived: dict[tuple[str, str], set[str]] = defaultdict(set)
    for publisher in (i for i in by_id.values() if i.kind.publishes and not i.endpoint):
        todo = [((publisher.container, publisher.ros_name), "")]
        while todo:
            (where, ros_name), route = todo.pop()
            arrived[(where, ros_name)].add(publisher.id)
            crossed = route.split(",") if route else []
            assert len(set(crossed)) == len(crossed), "a message crossed a connection twice"
            endpoint = endpoints.get(where)
            for relay_from in endpoint.interfaces if endpoint else ():
                if not relay_from.kind.subscribes or relay_from.ros_name != ros_name:
                    continue
                for relay in relay_from.relays:
                    if f"{publisher.id}|{route}" in relay.passes:
                        peer = next(
                            i for i in endpoints[relay.container].interfaces
                            if i.name == relay.interface
                        )  # fmt: skip
                        todo.append(
                            (
                                (relay.container, peer.ros_name),
                                ",".join([*crossed, relay.connection]),
                            )
                        )
    for interface in by_id.values():
        if interface.kind.subscribes:
            assert arrived[(interface.container, interface.ros_name)] == set(interface.sources), (
                interface.id
            )


def follow_goals(plan: Any, client: Any, server: Any) -> None:
    """A goal the client sends, carried as the stand-ins carry it: from the endpoint
    standing in for the server where it is (same ROS name) to that stand-in's peer, and
    so on, must reach the server's container under the server's name; the answers go
    back to every stand-in it passed (each relay lists it among its peers)."""
    endpoints = {c.name: c.endpoint for c in plan.containers if c.endpoint is not None}
    where, ros_name, passed = client.container, client.ros_name, set()
    while (where, ros_name) != (server.container, server.ros_name):
        assert (where, ros_name) not in passed, "a goal went round in a circle"
        passed.add((where, ros_name))
        endpoint = endpoints[where]
        (stand_in,) = [
            i
            for i in endpoint.interfaces
            if i.kind.serves and i.kind.family is ACTION and i.ros_name == ros_name
        ]
        peer_container, peer_name = stand_in.forward
        (relay,) = [i for i in endpoints[peer_container].interfaces if i.name == peer_name]
        assert (stand_in.container, stand_in.name) in relay.peers, "no way back for answers"
        assert relay.server == server.id
        where, ros_name = relay.container, relay.ros_name


@st.composite
def fleets_and_selections(draw):
    spec = draw(fleet_specs(actions=True))
    selected = draw(st.sets(st.sampled_from(spec.features()))) if spec.elements else set()
    return spec, selected


@settings(max_examples=examples(60), deadline=None)
@given(fleets_and_selections())
def test_every_output_carries_exactly_the_flow_table(case):
    spec, selected = case
    with tempfile.TemporaryDirectory() as scratch:
        line = load_product_line(write_line(spec, Path(scratch) / "line"))
        selection = selection_from_list(",".join(["Root", *sorted(selected)]))
        product = resolve(line, selection).product
        table = {(f.kind, name(f.source), name(f.target)) for f in product.flows}
        assert table == reachability(product.system)
        event(f"action flows: {min(sum(f.kind == ACTION for f in product.flows), 3)}")

        bundle = build_bundle(product, BundleOptions(render_diagrams=False))
        files = bundle.files
        expected = expected_deliveries(product)
        assert rapyuta_deliveries(files) == as_topics(expected)
        event(f"{len(expected)} deliveries between places")
        target(float(len(expected)))  # steer towards products whose data crosses places
        if "zenoh/" in bundle.skipped:  # the bundle says why Zenoh cannot carry it
            event("zenoh: " + bundle.skipped["zenoh/"].split(":")[1][:40])
            assert bundle.skipped["zenoh/"].startswith("Zenoh cannot carry this product: ")
        else:
            assert zenoh_deliveries(files) == expected

        folder = Path(scratch) / "bundle"
        write_bundle(files, folder)
        check_smoke_plan(product, folder)
